//! `glview serve PATH`: one process renders for every browser that opens its address. The
//! main thread holds the one GL context and draws every viewer's view in turn
//! ([`scheduler`]); a thread per connection reads its requests and messages ([`conn`]);
//! what crosses the socket is in [`protocol`] and docs/serve.md.
mod conn;
mod http;
mod models;
mod protocol;
mod render;
mod scheduler;

use crate::cli::ServeCommand;
use glview::session::Session;
use glview::{Error, Result};
use std::net::{SocketAddr, TcpListener, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Connections being answered at once beyond the viewers (page loads, refused requests):
/// more are closed at once, so a flood cannot take every thread.
const SPARE_CONNECTIONS: usize = 64;

fn check(cmd: &ServeCommand, addr: &SocketAddr) -> Result<()> {
    if cmd.no_token && !addr.ip().is_loopback() {
        return Err(Error::Usage(format!(
            "--no-token is only allowed on a loopback address (127.0.0.1 or ::1), not {addr}: \
             anyone on the network could open the viewer"
        )));
    }
    if let Some(t) = &cmd.token {
        if t.is_empty()
            || !t
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(Error::Usage(
                "--token: use letters, digits, - and _ only (it goes into a URL)".into(),
            ));
        }
    }
    if !(cmd.drag_scale > 0.0 && cmd.drag_scale <= 1.0) {
        return Err(Error::Usage("--drag-scale must be in (0, 1]".into()));
    }
    if !(1..=100).contains(&cmd.drag_quality) {
        return Err(Error::Usage("--drag-quality must be 1 to 100".into()));
    }
    if cmd.max_viewers == 0 || cmd.idle_timeout == 0 {
        return Err(Error::Usage(
            "--max-viewers and --idle-timeout must be at least 1".into(),
        ));
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
    // The context is made now: a machine without one fails here, not at the first viewer.
    let mut first = base.clone();
    first.load.model = models.first().1.map(Into::into);
    let mut session = Session::open(&first)?;
    session.keep_scenes(cmd.keep_scenes);
    // The first model is loaded before anyone asks (a broken one is the viewers' error).
    if let Err(e) = session.scene(&first) {
        log::warn!("{}: {e}", models.first().0);
    }
    let token = if cmd.no_token {
        None
    } else {
        Some(cmd.token.clone().unwrap_or_else(http::random_token))
    };
    let presenter_key = http::random_token();
    let (events, rx) = std::sync::mpsc::channel();
    let presenter_online = Arc::new(AtomicBool::new(false));
    let shared = Arc::new(conn::Shared {
        token: token.clone(),
        presenter_key: presenter_key.clone(),
        models: models.names(),
        first_model: models.first().0.to_string(),
        size: base.picture.size,
        max_viewers: cmd.max_viewers,
        idle_timeout: Duration::from_secs(cmd.idle_timeout),
        events,
        viewers: AtomicUsize::new(0),
        next_id: AtomicU64::new(1),
        presenter_online: presenter_online.clone(),
    });
    let query = token.map(|t| format!("?token={t}")).unwrap_or_default();
    let sep = if query.is_empty() { '?' } else { '&' };
    println!("glview serve: open http://{local}/{query}");
    println!("glview serve: presenter http://{local}/{query}{sep}present={presenter_key}");
    println!(
        "glview serve: {} model(s), views {w}x{h}, at most {} viewers",
        models.names().len(),
        cmd.max_viewers
    );
    use std::io::Write;
    let _ = std::io::stdout().flush();
    let limit = cmd.max_viewers + SPARE_CONNECTIONS;
    std::thread::Builder::new()
        .name("glview-accept".into())
        .spawn(move || accept(listener, shared, limit))
        .map_err(|e| Error::Usage(format!("cannot start a thread: {e}")))?;
    // An OSMesa context keeps the size it was made with (a new size is a new context and
    // every scene loaded again): its views keep one size, previews included.
    let fixed_size = session.fixed_size();
    if fixed_size {
        log::warn!("OSMesa: previews are full size and views keep the size --size gives");
    }
    let config = scheduler::Config {
        still_delay: Duration::from_millis(cmd.still_delay),
        drag_scale: if fixed_size { 1.0 } else { cmd.drag_scale },
        drag_quality: cmd.drag_quality,
        fixed_size,
    };
    scheduler::Scheduler::new(session, base, models, config, presenter_online).run(&rx);
    Ok(())
}

/// Takes connections, each on a thread of its own, at most `limit` at once.
fn accept(listener: TcpListener, shared: Arc<conn::Shared>, limit: usize) {
    let live = Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        let Ok(stream) = stream else {
            continue;
        };
        if live.load(Ordering::SeqCst) >= limit {
            drop(stream);
            continue;
        }
        live.fetch_add(1, Ordering::SeqCst);
        let (shared, done) = (shared.clone(), live.clone());
        let spawned = std::thread::Builder::new()
            .name("glview-conn".into())
            .stack_size(256 * 1024)
            .spawn(move || {
                conn::handle(stream, &shared);
                done.fetch_sub(1, Ordering::SeqCst);
            });
        if spawned.is_err() {
            live.fetch_sub(1, Ordering::SeqCst);
            log::warn!("cannot start a connection thread");
        }
    }
}
