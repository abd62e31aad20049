//! `glview serve PATH`: one process renders for every browser that opens its address. The
//! main thread schedules every viewer's frames ([`scheduler`]) on a pool of render threads,
//! each with a GL context and scenes of its own ([`pool`]); connections are tasks on a
//! small tokio runtime ([`conn`], [`socket`]), talking to the scheduler through bounded
//! queues ([`queues`]); what crosses the socket is in [`protocol`] and docs/serve.md.
mod conn;
mod hosts;
mod http;
mod models;
mod pool;
mod protocol;
mod queues;
mod render;
mod scheduler;
mod socket;
mod web;

use crate::cli::ServeCommand;
use glview::{Error, Result};
use std::net::{SocketAddr, TcpListener, ToSocketAddrs};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

/// A `--token` shorter than this could be guessed.
const MIN_TOKEN: usize = 16;
/// Each render thread holds a context and its own copy of its scenes.
const MAX_RENDER_THREADS: usize = 64;

/// `--render-threads` when not given: a quarter of the cores, 1 to 4. llvmpipe already
/// spreads each frame over every core, and the network (2 threads), the encoders (up to 4)
/// and the loads (half the cores) need theirs; on a GPU the threads overlap one frame's
/// CPU work and read-back with another's drawing, and more than 4 only add copies of the
/// scenes.
fn default_render_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    (cores / 4).clamp(1, 4)
}

fn check(cmd: &ServeCommand, addr: &SocketAddr) -> Result<()> {
    if cmd.no_token && !addr.ip().is_loopback() {
        return Err(Error::Usage(format!(
            "--no-token is only allowed on a loopback address (127.0.0.1 or ::1), not {addr}: \
             anyone on the network could open the viewer"
        )));
    }
    if let Some(t) = &cmd.token {
        if !t
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(Error::Usage(
                "--token: use letters, digits, - and _ only (it goes into a URL)".into(),
            ));
        }
        if t.len() < MIN_TOKEN {
            return Err(Error::Usage(format!(
                "--token: at least {MIN_TOKEN} characters (a short one can be guessed)"
            )));
        }
    }
    if !(cmd.drag_scale > 0.0 && cmd.drag_scale <= 1.0) {
        return Err(Error::Usage("--drag-scale must be in (0, 1]".into()));
    }
    if !(1..=100).contains(&cmd.drag_quality) {
        return Err(Error::Usage("--drag-quality must be 1 to 100".into()));
    }
    if cmd.max_viewers == 0
        || cmd.idle_timeout == 0
        || cmd.max_per_address == 0
        || cmd.max_viewers_per_address == 0
    {
        return Err(Error::Usage(
            "--max-viewers, --max-per-address, --max-viewers-per-address and --idle-timeout \
             must be at least 1"
                .into(),
        ));
    }
    if cmd
        .render_threads
        .is_some_and(|n| !(1..=MAX_RENDER_THREADS).contains(&n))
    {
        return Err(Error::Usage(format!(
            "--render-threads must be 1 to {MAX_RENDER_THREADS}"
        )));
    }
    Ok(())
}

pub fn run(cmd: &ServeCommand) -> Result<()> {
    let mut base = cmd.opts.0.clone();
    if let Some(e) = &cmd.opts.1 {
        return Err(e.clone().into());
    }
    let addr = cmd
        .bind
        .to_socket_addrs()
        .ok()
        .and_then(|mut a| a.next())
        .ok_or_else(|| Error::Usage(format!("--bind {}: not an address:port", cmd.bind)))?;
    check(cmd, &addr)?;
    let (w, h) = base.picture.size;
    if w > protocol::MAX_SIZE || h > protocol::MAX_SIZE {
        return Err(Error::Usage(format!(
            "--size: a view is at most {0}x{0}",
            protocol::MAX_SIZE
        )));
    }
    let models = models::Models::scan(base.load.model.take().as_deref())?;
    let listener = TcpListener::bind(addr)
        .map_err(|e| Error::Unsupported(format!("cannot listen on {addr} (--bind): {e}")))?;
    let local = listener
        .local_addr()
        .map_err(|e| Error::Usage(e.to_string()))?;
    let models = Arc::new(models);
    // The contexts are made now: a machine without one fails here, not at the first viewer.
    let mut first = base.clone();
    first.load.model = models.first().1.map(Into::into);
    let (events, rx) = std::sync::mpsc::channel();
    let threads = cmd.render_threads.unwrap_or_else(default_render_threads);
    let pool_shared = Arc::new(pool::Shared {
        models: models.clone(),
        encoders: Arc::new(encoders()?),
        events: events.clone(),
        drawn: Default::default(),
    });
    let (pool, fixed_size) = pool::Pool::start(threads, &first, cmd.keep_scenes, &pool_shared)?;
    let token = if cmd.no_token {
        None
    } else {
        Some(cmd.token.clone().unwrap_or_else(http::random_token))
    };
    let presenter_key = http::random_token();
    let presenter_online = Arc::new(AtomicBool::new(false));
    let public = public_authority(cmd.public_url.as_deref())?;
    let mut shared = conn::Shared::new(
        token.clone(),
        presenter_key.clone(),
        (models.names(), models.first().0.to_string()),
        base.picture.size,
        conn::Limits {
            max_viewers: cmd.max_viewers,
            max_per_address: cmd.max_per_address,
            max_viewers_per_address: cmd.max_viewers_per_address,
            idle_timeout: Duration::from_secs(cmd.idle_timeout),
        },
        hosts::Hosts::new(&local, public.as_deref()),
        events.clone(),
        presenter_online.clone(),
    );
    let embed = embed_origins(&cmd.embed_origin)?;
    if !embed.is_empty() {
        shared.frame_ancestors = format!("'self' {}", embed.join(" "));
        // A frame of another site gets the cookie only as SameSite=None, and browsers take
        // that only with Secure (HTTPS).
        if cmd
            .public_url
            .as_deref()
            .is_some_and(|u| u.starts_with("https://"))
        {
            shared.cookie_site = "SameSite=None; Secure";
        }
    }
    shared.web = local_mode(cmd, &base, &models)?;
    let draws_local = shared.web.is_some();
    let shared = Arc::new(shared);
    let query = token.map(|t| format!("?token={t}")).unwrap_or_default();
    let sep = if query.is_empty() { '?' } else { '&' };
    let open = match &cmd.public_url {
        Some(u) => u.trim_end_matches('/').to_string(),
        None => format!("http://{local}"),
    };
    println!("glview serve: listening on {local}");
    println!("glview serve: open {open}/{query}");
    println!("glview serve: presenter {open}/{query}{sep}present={presenter_key}");
    if !embed.is_empty() {
        println!(
            "glview serve: embed <iframe src=\"{open}/{query}\" width=\"{w}\" height=\"{h}\" \
             style=\"border:0;max-width:100%\" allow=\"fullscreen\"></iframe>"
        );
    }
    println!(
        "glview serve: {} model(s), views {w}x{h}, at most {} viewers ({} per address), \
         {threads} render thread(s)",
        models.names().len(),
        cmd.max_viewers,
        cmd.max_viewers_per_address
    );
    use std::io::Write;
    let _ = std::io::stdout().flush();
    start_network(listener, shared)?;
    // An OSMesa context keeps the size it was made with (a new size is a new context and
    // every scene loaded again): its views keep one size, previews included.
    if fixed_size {
        log::warn!("OSMesa: previews are full size and views keep the size --size gives");
    }
    let config = scheduler::Config {
        still_delay: Duration::from_millis(cmd.still_delay),
        drag_scale: if fixed_size { 1.0 } else { cmd.drag_scale },
        drag_quality: cmd.drag_quality,
        fixed_size,
        max_size: base.picture.size,
        local: draws_local,
    };
    scheduler::Scheduler::new(pool, base, models, config, presenter_online, events).run(&rx);
    Ok(())
}

/// The browser build for local mode: `--web-dir`'s (an error when it is not there), else
/// the one `glview export --live` would find, when it is there; none with `--stream-only`.
fn local_mode(
    cmd: &ServeCommand,
    base: &glview::Options,
    models: &Arc<models::Models>,
) -> Result<Option<Arc<web::Web>>> {
    if cmd.stream_only {
        return Ok(None);
    }
    match web::Web::open(cmd.web_dir.as_deref(), base, models.clone()) {
        Ok(w) => Ok(Some(Arc::new(w))),
        Err(e) if cmd.web_dir.is_some() => Err(e),
        Err(e) => {
            log::warn!("local mode is off (every page gets the stream): {e}");
            Ok(None)
        }
    }
}

/// The encoders: a pool of their own, because a model's load fills rayon's global pool
/// (its parse, normals and clusters are parallel) and an encode queued behind it held
/// every other viewer's frame back by ~100 ms (measured).
fn encoders() -> Result<rayon::ThreadPool> {
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    rayon::ThreadPoolBuilder::new()
        .num_threads(cores.clamp(1, 4))
        .thread_name(|i| format!("glview-encode-{i}"))
        .build()
        .map_err(|e| Error::Unsupported(format!("cannot start the encoders: {e}")))
}

/// The connections' runtime on two threads of its own (the render thread stays this one).
fn start_network(listener: TcpListener, shared: Arc<conn::Shared>) -> Result<()> {
    raise_descriptor_limit();
    let fail = |e: std::io::Error| Error::Unsupported(format!("cannot start the server: {e}"));
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .thread_name("glview-net")
        .enable_io()
        .enable_time()
        .build()
        .map_err(fail)?;
    listener.set_nonblocking(true).map_err(fail)?;
    let listener = {
        let _guard = runtime.enter();
        tokio::net::TcpListener::from_std(listener).map_err(fail)?
    };
    std::thread::Builder::new()
        .name("glview-accept".into())
        .spawn(move || runtime.block_on(conn::accept(listener, shared)))
        .map_err(fail)?;
    Ok(())
}

/// Idle connections cost a descriptor each: the soft limit goes up to the hard one, so a
/// thousand of them leave room for the viewers. (Windows has no such limit on sockets.)
#[cfg(not(unix))]
fn raise_descriptor_limit() {}

/// Idle connections cost a descriptor each: the soft limit goes up to the hard one, so a
/// thousand of them leave room for the viewers.
#[cfg(unix)]
fn raise_descriptor_limit() {
    let mut lim = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit/setrlimit read and write the one struct given.
    unsafe {
        if libc::getrlimit(libc::RLIMIT_NOFILE, &mut lim) == 0 && lim.rlim_cur < lim.rlim_max {
            lim.rlim_cur = lim.rlim_max;
            libc::setrlimit(libc::RLIMIT_NOFILE, &lim);
        }
    }
}

/// `--embed-origin`s as CSP sources: `scheme://host[:port]`, nothing else.
fn embed_origins(given: &[String]) -> Result<Vec<String>> {
    given
        .iter()
        .map(|o| {
            let o = o.trim_end_matches('/');
            let rest = o
                .strip_prefix("https://")
                .or_else(|| o.strip_prefix("http://"))
                .unwrap_or("");
            let ok = !rest.is_empty()
                && rest
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || ".-:[]".contains(c));
            if ok {
                Ok(o.to_ascii_lowercase())
            } else {
                Err(Error::Usage(format!(
                    "--embed-origin {}: an origin is http(s)://host[:port], no path",
                    http::clip(o)
                )))
            }
        })
        .collect()
}

/// `--public-url`'s host and port as a `Host` header names them (lower case).
fn public_authority(url: Option<&str>) -> Result<Option<String>> {
    let Some(url) = url else {
        return Ok(None);
    };
    let rest = url
        .strip_prefix("https://")
        .or_else(|| url.strip_prefix("http://"))
        .ok_or_else(|| {
            Error::Usage(format!(
                "--public-url {url}: an http:// or https:// address"
            ))
        })?;
    let authority = rest.split('/').next().unwrap_or("");
    if authority.is_empty() || authority.contains('@') {
        return Err(Error::Usage(format!("--public-url {url}: no host in it")));
    }
    Ok(Some(authority.to_ascii_lowercase()))
}
