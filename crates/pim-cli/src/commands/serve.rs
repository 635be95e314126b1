//! `pim serve`: the scene editor in the browser (crate pim-serve), on this machine.

use crate::error::Failure;
use crate::serve_args::ServeArgs;
use anyhow::Result;
use std::process::ExitCode;

/// `pim serve`.
pub fn run(a: &ServeArgs) -> Result<ExitCode> {
    let (root, initial) = if a.path.is_dir() {
        (a.path.clone(), None)
    } else if a.path.is_file() {
        let root = a
            .path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map_or_else(|| std::path::PathBuf::from("."), |p| p.to_path_buf());
        let name = a.path.file_name().map(|n| n.to_string_lossy().to_string());
        (root, name)
    } else {
        return Err(Failure::Input(format!(
            "{}: no such folder or case file to serve",
            a.path.display()
        ))
        .into());
    };
    let root = root
        .canonicalize()
        .map_err(|e| Failure::Input(format!("{}: {e}", root.display())))?;
    let loopback = matches!(a.host.as_str(), "127.0.0.1" | "localhost" | "::1");
    if !loopback {
        eprintln!(
            "pim serve: warning: listening on {} makes the editor reachable from other machines \
             (each still needs the token); files in {} can be read and written through it",
            a.host,
            root.display()
        );
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| Failure::Output(format!("pim serve: {e}")))?;
    runtime.block_on(async {
        let listener = bind(&a.host, a.port).await?;
        let port = listener
            .local_addr()
            .map_err(|e| Failure::Output(format!("pim serve: {e}")))?
            .port();
        let token = pim_serve::Served::new_token();
        let shown = if a.host.contains(':') {
            format!("[{}]", a.host)
        } else {
            a.host.clone()
        };
        let url = format!("http://{shown}:{port}/?token={token}");
        super::print_out(&format!(
            "pim serve: {} on {url}\npim serve: open that address in a browser; Ctrl-C stops \
             the server\n",
            root.display()
        ))?;
        if a.open {
            open_browser(&url);
        }
        let served = pim_serve::Served {
            root,
            initial,
            token,
            hosts: if loopback {
                vec![]
            } else {
                vec![a.host.clone()]
            },
        };
        pim_serve::run(listener, served)
            .await
            .map_err(|e| Failure::Output(format!("pim serve: {e}")))?;
        Ok::<(), anyhow::Error>(())
    })?;
    Ok(ExitCode::SUCCESS)
}

/// The listener on `port`, or the next free one of the ten after it (0: any free port).
async fn bind(host: &str, port: u16) -> Result<tokio::net::TcpListener> {
    let tries: Vec<u16> = if port == 0 {
        vec![0]
    } else {
        (port..=port.saturating_add(10)).collect()
    };
    let mut last = None;
    for p in tries {
        match tokio::net::TcpListener::bind((host, p)).await {
            Ok(l) => return Ok(l),
            Err(e) => last = Some(e),
        }
    }
    Err(Failure::Output(format!(
        "pim serve: cannot listen on {host} port {port} or the ten after it: {}",
        last.map_or_else(String::new, |e| e.to_string())
    ))
    .into())
}

/// Opens `url` in the desktop's browser; a failure only warns.
fn open_browser(url: &str) {
    if let Err(e) = webbrowser::open(url) {
        eprintln!("pim serve: warning: could not open a browser ({e}); open the address yourself");
    }
}
