//! Who may ask and which files they may touch.

use std::path::{Component, Path, PathBuf};

/// The checks of every request: the token and the Host header.
#[derive(Debug, Clone)]
pub struct Guard {
    /// The run's token.
    pub token: String,
    /// Host names allowed besides the loopback ones.
    pub hosts: Vec<String>,
}

impl Guard {
    /// Whether a request's `Host` header (`name` or `name:port`) names this server: a loopback
    /// name, or one the server was told to bind.
    pub fn host_allowed(&self, host: Option<&str>) -> bool {
        let Some(host) = host else { return false };
        let name = if let Some(rest) = host.strip_prefix('[') {
            // [::1]:8765
            rest.split(']').next().unwrap_or("")
        } else {
            host.rsplit_once(':').map_or(host, |(n, _)| n)
        };
        let name = name.to_ascii_lowercase();
        matches!(name.as_str(), "127.0.0.1" | "localhost" | "::1")
            || self.hosts.iter().any(|h| h.eq_ignore_ascii_case(&name))
    }

    /// Whether a `Cookie` header carries the run's token.
    pub fn cookie_allowed(&self, cookie: Option<&str>) -> bool {
        cookie.is_some_and(|c| {
            c.split(';')
                .filter_map(|kv| kv.trim().split_once('='))
                .any(|(k, v)| k == COOKIE && same_secret(v, &self.token))
        })
    }
}

/// Whether `given` is the secret `secret`, compared in time that does not depend on where they
/// first differ (so the token cannot be guessed a character at a time by timing).
pub fn same_secret(given: &str, secret: &str) -> bool {
    use subtle::ConstantTimeEq;
    given.len() == secret.len() && bool::from(given.as_bytes().ct_eq(secret.as_bytes()))
}

/// The cookie that holds the token.
pub(crate) const COOKIE: &str = "pim_token";

/// The file `relative` names inside `root`, if it is a case file (`.toml`) inside it: no
/// absolute path, no `..`, and (for a file that exists) no link that leads outside. `None`
/// for anything else.
pub fn inside(root: &Path, relative: &str) -> Option<PathBuf> {
    inside_of(root, relative, &["toml"])
}

/// [`inside`] for a file of one of the kinds `kinds` (extensions, lower case).
pub fn inside_of(root: &Path, relative: &str, kinds: &[&str]) -> Option<PathBuf> {
    let rel = Path::new(relative);
    let kind = rel
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if relative.is_empty()
        || !kind.is_some_and(|k| kinds.contains(&k.as_str()))
        || !rel.components().all(|c| matches!(c, Component::Normal(_)))
    {
        return None;
    }
    let root = root.canonicalize().ok()?;
    let path = root.join(rel);
    // The nearest existing ancestor must lie inside the root (links resolved).
    let mut probe = path.clone();
    loop {
        if let Ok(real) = probe.canonicalize() {
            return real.starts_with(&root).then_some(path);
        }
        if !probe.pop() {
            return None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hosts() {
        let g = Guard {
            token: "t".into(),
            hosts: vec![],
        };
        for ok in ["127.0.0.1:8765", "localhost:1", "LOCALHOST", "[::1]:8765"] {
            assert!(g.host_allowed(Some(ok)), "{ok}");
        }
        for bad in ["evil.example:8765", "127.0.0.1.evil.example", "", "[::2]:1"] {
            assert!(!g.host_allowed(Some(bad)), "{bad}");
        }
        assert!(!g.host_allowed(None));
    }

    #[test]
    fn cookies() {
        let g = Guard {
            token: "abc".into(),
            hosts: vec![],
        };
        assert!(g.cookie_allowed(Some("x=1; pim_token=abc")));
        assert!(!g.cookie_allowed(Some("pim_token=abd")));
        assert!(!g.cookie_allowed(Some("pim_tokenx=abc")));
        assert!(!g.cookie_allowed(None));
    }

    #[test]
    fn paths() {
        let root = std::env::temp_dir().join(format!("pim-serve-guard-{}", std::process::id()));
        std::fs::create_dir_all(root.join("sub")).unwrap();
        assert!(inside(&root, "a.toml").is_some());
        assert!(inside(&root, "sub/b.toml").is_some());
        for bad in [
            "../a.toml",
            "sub/../../a.toml",
            "/etc/passwd.toml",
            "a.txt",
            "",
            "./a.toml",
        ] {
            assert!(inside(&root, bad).is_none(), "{bad}");
        }
    }
}
