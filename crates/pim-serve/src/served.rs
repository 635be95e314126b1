//! What a server serves.

use std::path::PathBuf;

/// The largest request body accepted, bytes (a case file is a few kilobytes).
pub const BODY_LIMIT: usize = 1 << 20;

/// What the server serves.
#[derive(Debug, Clone)]
pub struct Served {
    /// The folder whose case files the page opens and saves.
    pub root: PathBuf,
    /// The case opened first (a path inside `root`), when one was named.
    pub initial: Option<String>,
    /// The run's token.
    pub token: String,
    /// The host names a request may name besides the loopback ones.
    pub hosts: Vec<String>,
}

impl Served {
    /// A new run's token: 128 random bits in hex.
    pub fn new_token() -> String {
        format!("{:032x}", rand::random::<u128>())
    }
}

/// A server: what it serves, and each case's last reconstruction (what a live answer follows).
#[derive(Debug)]
pub(crate) struct Server {
    pub(crate) served: Served,
    pub(crate) last: std::sync::Mutex<std::collections::HashMap<String, pim_reconstruct::Outcome>>,
    /// The uncertainty studies started from the page.
    pub(crate) studies: crate::study::Studies,
}
