//! The arguments of `pim serve`.

use std::path::PathBuf;

/// What `pim serve --help` adds below the options.
pub const SERVE_HELP: &str = "Examples:
  pim serve examples/cases                 serve the example cases; open the address printed
  pim serve examples/cases/reconstruction_us.toml --open
  pim serve . --port 0                     any free port

Safety: the server listens on 127.0.0.1 (this machine only) unless --host widens it; every
request needs the run's token, which the printed address carries (the page keeps it as a
cookie); requests whose Host header is not this machine's name are refused; only .toml files
inside the folder served are read or written. Stop it with Ctrl-C.";

/// `pim serve`.
#[derive(clap::Args, Debug)]
pub struct ServeArgs {
    /// A folder of case files, or one case file (its folder is served and it opens first).
    #[arg(default_value = ".")]
    pub path: PathBuf,
    /// The address to listen on. Anything but a loopback address makes the editor reachable
    /// from other machines (with the token): a warning says so.
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    /// The port; when it is taken, the next free one of the ten after it. 0: any free port.
    #[arg(long, default_value_t = 8765)]
    pub port: u16,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
}
