//! The `Host` header check: a page of another site that renames itself to this server's
//! address (DNS rebinding) sends its own name as the `Host`, and is refused with 421.
use std::net::{IpAddr, Ipv6Addr, SocketAddr};

/// The `Host` values this server answers to.
pub enum Hosts {
    /// These `host[:port]`s (lower case): the bind address's, `localhost`'s on a loopback
    /// one, `--public-url`'s.
    Listed(Vec<String>),
    /// Bound to every address (0.0.0.0, [::]) without `--public-url`: any IP literal and
    /// these names of this machine, on any port (an attacker's page cannot be an IP
    /// literal's origin and still reach the server under a name it controls).
    ThisMachine(Vec<String>),
}

impl Hosts {
    /// The names a server bound to `local` answers to, with `--public-url`'s authority.
    pub fn new(local: &SocketAddr, public: Option<&str>) -> Hosts {
        let port = local.port();
        let mut list: Vec<String> = public.into_iter().map(str::to_string).collect();
        let ip = local.ip();
        if ip.is_unspecified() {
            if list.is_empty() {
                return Hosts::ThisMachine(machine_names());
            }
            return Hosts::Listed(list);
        }
        list.push(local.to_string());
        if ip.is_loopback() {
            list.extend([
                format!("localhost:{port}"),
                format!("127.0.0.1:{port}"),
                format!("[::1]:{port}"),
            ]);
        }
        Hosts::Listed(list)
    }

    /// Whether a request naming `host` is answered.
    pub fn allows(&self, host: &str) -> bool {
        let host = host.to_ascii_lowercase();
        match self {
            Hosts::Listed(list) => list.contains(&host),
            Hosts::ThisMachine(names) => {
                let name = without_port(&host);
                let bracketed = name
                    .strip_prefix('[')
                    .and_then(|n| n.strip_suffix(']'))
                    .is_some_and(|n| n.parse::<Ipv6Addr>().is_ok());
                bracketed
                    || name.parse::<IpAddr>().is_ok()
                    || names.iter().any(|n| n == name.trim_end_matches('.'))
            }
        }
    }

    /// Why a refused request is refused (one line for the client).
    pub fn refusal(&self) -> &'static str {
        match self {
            Hosts::Listed(_) => {
                "this server does not answer to that host name (--public-url names one)"
            }
            Hosts::ThisMachine(_) => {
                "this server answers to its IP addresses and this machine's names only \
                 (--public-url names another)"
            }
        }
    }
}

/// `host` without its `:port` (an IPv6 literal keeps its brackets).
fn without_port(host: &str) -> &str {
    match host.rsplit_once(':') {
        Some((h, p)) if p.bytes().all(|b| b.is_ascii_digit()) && !h.ends_with(':') => {
            // "[::1]:8080" → "[::1]"; a bare IPv6 literal has no port to strip.
            if h.starts_with('[') == h.ends_with(']') {
                h
            } else {
                host
            }
        }
        _ => host,
    }
}

/// This machine's host name, as the system gives it.
#[cfg(unix)]
fn host_name() -> Option<String> {
    let mut buf = [0u8; 256];
    // SAFETY: gethostname writes at most buf.len() bytes into the buffer given.
    let ok = unsafe { libc::gethostname(buf.as_mut_ptr().cast(), buf.len()) } == 0;
    let end = buf.iter().position(|&b| b == 0).unwrap_or(0);
    ok.then(|| std::str::from_utf8(&buf[..end]).ok().map(str::to_string))
        .flatten()
}

/// This machine's NetBIOS name (what Windows' `hostname` prints).
#[cfg(windows)]
fn host_name() -> Option<String> {
    std::env::var("COMPUTERNAME").ok()
}

/// `localhost` and this machine's host name: as given, its first label, and its mDNS
/// `.local` name.
fn machine_names() -> Vec<String> {
    let mut names = vec!["localhost".to_string()];
    if let Some(name) = host_name()
        .map(|n| n.trim_end_matches('.').to_ascii_lowercase())
        .filter(|n| !n.is_empty())
    {
        let short = name.split('.').next().unwrap_or(&name).to_string();
        names.push(format!("{short}.local"));
        names.push(short);
        names.push(name);
    }
    names.dedup();
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn this_machine_is_ip_literals_and_its_names() {
        let h = Hosts::ThisMachine(vec!["localhost".into(), "lab7".into()]);
        for ok in [
            "10.0.0.5:8080",
            "10.0.0.5",
            "[::1]:80",
            "[fe80::1]",
            "LAB7:8080",
            "lab7.",
        ] {
            assert!(h.allows(ok), "{ok}");
        }
        for bad in [
            "evil.example",
            "lab7.evil.example:8080",
            "10.0.0.5.nip.io",
            "",
            "[lab7]",
        ] {
            assert!(!h.allows(bad), "{bad}");
        }
    }
}
