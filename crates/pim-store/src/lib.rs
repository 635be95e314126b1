//! # pim-store: the case file on disk
//!
//! The one way every face of the toolkit reads and writes a case file (`pim set`, the editor's
//! Save, Python's `edit_case`); the library crates below it do no file I/O. A case file is the
//! user's work, so a write here is never lost, never half written and never silently
//! overwritten:
//!
//! - **Checked first.** The text is read with every check `pim fit` makes
//!   ([`pim_studies::check::check_text`]); a refused text is never written, and the error is
//!   the one `pim fit` would give (file, line, field).
//! - **Atomic.** The text goes to a uniquely named temporary file in the same folder
//!   (`.NAME.XXXXXX.pim-tmp`), is flushed and synced, takes the target's mode (and owner, where
//!   the process may give it), and is renamed over the target; the folder is synced after. A
//!   reader sees the old file or the new one, never a part; a process killed at any moment
//!   leaves the old file or the new one. A temporary left by a killed writer is removed by the
//!   next write of the same file.
//! - **Versioned.** Every read carries the text's [`Version`] (a SHA-256 of its bytes). A write
//!   that names the version it started from is refused with [`StoreError::Conflict`] when the
//!   file has changed since (another editor, another client, another `pim set`), and the
//!   conflict carries the file's current text and version.
//! - **Serialised.** A write holds an exclusive lock on the file (`flock`) from the moment it
//!   reads the current version until its rename; writers in one process or in several wait
//!   for each other, so no update is lost. A lock taken on a file that was replaced meanwhile
//!   is let go and taken again on the new one.
//! - **Only regular files.** A FIFO, device, socket or folder is refused before it is read
//!   (opened without blocking, so a FIFO cannot hang the reader); a read stops one byte past
//!   the size limit. A symbolic link is followed to its real file, which is edited in place of
//!   the link (the link itself is never replaced); a link to nothing is refused, and with a
//!   folder given (`pim serve`) the real file must lie inside it. A file nobody may write
//!   (mode without any write bit, such as 0444) is refused, not replaced.

use sha2::{Digest, Sha256};
use std::fs::File;
use std::io::{Read, Seek, Write};
use std::os::unix::fs::{MetadataExt, OpenOptionsExt, PermissionsExt};
use std::path::{Path, PathBuf};

pub use pim_case::case::MAX_CASE_BYTES;

/// The version of a case file's text: the hex SHA-256 of its bytes (64 characters).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Version(pub String);

impl Version {
    /// The version of `text`.
    pub fn of(text: &str) -> Self {
        let digest = Sha256::digest(text.as_bytes());
        Version(digest.iter().map(|b| format!("{b:02x}")).collect())
    }

    /// Whether `given` names this version: the whole hex digest, or a prefix of at least 8
    /// characters (as `git` abbreviates), case-insensitive.
    pub fn matches(&self, given: &str) -> bool {
        let g = given.trim().to_ascii_lowercase();
        g.len() >= 8 && self.0.starts_with(&g)
    }

    /// The first 12 characters, for messages.
    pub fn short(&self) -> &str {
        &self.0[..12]
    }
}

impl std::fmt::Display for Version {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// A case file's text as read, with its version.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Stored {
    /// The text.
    pub text: String,
    /// Its version.
    pub version: Version,
}

/// Why a case file was not read or not written. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// The text is not a case `pim fit` reads: its message (file, line, field). Nothing was
    /// written.
    #[error("{0}")]
    Refused(String),
    /// The file changed since the version the write started from. Nothing was written.
    #[error(
        "{file}: changed on disk since it was read (version {} then, {} now): not \
         written; read it again, or write with the current version to replace it",
        expected, current.version.short()
    )]
    Conflict {
        /// The file.
        file: String,
        /// The version the write named.
        expected: String,
        /// The file as it is now.
        current: Stored,
    },
    /// A file the store does not read or write: not a regular file, a link to nothing or
    /// outside the folder, read-only, too large, not UTF-8.
    #[error("{file}: {why}")]
    Unusable {
        /// The file.
        file: String,
        /// Why.
        why: String,
    },
    /// The file does not exist.
    #[error("{file}: no such file")]
    Missing {
        /// The file.
        file: String,
    },
    /// The system refused a read or a write.
    #[error("{file}: cannot {action}: {source}")]
    Io {
        /// The file.
        file: String,
        /// `read` or `write`.
        action: &'static str,
        /// The system's error.
        source: std::io::Error,
    },
}

fn io<'a>(file: &'a str, action: &'static str) -> impl FnOnce(std::io::Error) -> StoreError + 'a {
    move |source| match source.kind() {
        std::io::ErrorKind::NotFound => StoreError::Missing {
            file: file.to_string(),
        },
        _ => StoreError::Io {
            file: file.to_string(),
            action,
            source,
        },
    }
}

/// A file the case layer refuses to read (not a regular file, too large, not UTF-8), its
/// message without the file's name (the error adds it).
fn unusable_input(file: &str, e: &pim_case::InputError) -> StoreError {
    let why = e
        .message
        .strip_prefix(&format!("{file}: "))
        .unwrap_or(&e.message);
    unusable(file, why)
}

fn unusable(file: &str, why: impl Into<String>) -> StoreError {
    StoreError::Unusable {
        file: file.to_string(),
        why: why.into(),
    }
}

/// Opens `path` for reading without blocking (a FIFO opened this way does not wait for a
/// writer) and refuses anything but a regular file of at most `max_bytes`.
fn open_regular(file: &str, path: &Path, max_bytes: u64) -> Result<File, StoreError> {
    let f = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32)
        .open(path)
        .map_err(io(file, "read"))?;
    let meta = f.metadata().map_err(io(file, "read"))?;
    pim_case::input::check_file(file, &meta, max_bytes).map_err(|e| unusable_input(file, &e))?;
    Ok(f)
}

fn read_open(file: &str, f: &mut File, max_bytes: u64) -> Result<Stored, StoreError> {
    f.rewind().map_err(io(file, "read"))?;
    let text = pim_case::input::read_text(file, &mut *f, max_bytes)
        .map_err(|e| unusable_input(file, &e))?;
    let version = Version::of(&text);
    Ok(Stored { text, version })
}

/// Reads a text file of at most `max_bytes` bytes: a regular file only (a FIFO, device or
/// socket is refused without waiting on it), UTF-8, with its version.
///
/// # Errors
/// [`StoreError::Missing`], [`StoreError::Unusable`] or [`StoreError::Io`], naming `path`.
pub fn read(path: &Path, max_bytes: u64) -> Result<Stored, StoreError> {
    let file = path.display().to_string();
    let mut f = open_regular(&file, path, max_bytes)?;
    read_open(&file, &mut f, max_bytes)
}

/// Reads a file's bytes as [`read`] does (a regular file of at most `max_bytes`), for images.
///
/// # Errors
/// As [`read`].
pub fn read_bytes(path: &Path, max_bytes: u64) -> Result<Vec<u8>, StoreError> {
    let file = path.display().to_string();
    let f = open_regular(&file, path, max_bytes)?;
    let mut bytes = Vec::new();
    f.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io(&file, "read"))?;
    if bytes.len() as u64 > max_bytes {
        return Err(unusable(
            &file,
            format!("is larger than the {max_bytes} bytes accepted for this kind of file"),
        ));
    }
    Ok(bytes)
}

/// How a write may go.
#[derive(Debug, Clone, Default)]
pub struct WriteOptions<'a> {
    /// The version the text was made from: the write is refused with
    /// [`StoreError::Conflict`] if the file is no longer that version. `None` replaces
    /// whatever the file holds.
    pub expected: Option<&'a str>,
    /// A folder the real file (links followed) must lie inside (`pim serve`'s folder).
    pub inside: Option<&'a Path>,
    /// The name messages give the file (default: the path as given).
    pub name: Option<&'a str>,
}

/// The real file a path names (links followed), which must exist, be a regular file someone
/// may write, and lie inside `inside` when one is given.
fn real_target(file: &str, path: &Path, inside: Option<&Path>) -> Result<PathBuf, StoreError> {
    let link = std::fs::symlink_metadata(path).map_err(io(file, "write"))?;
    let real = match std::fs::canonicalize(path) {
        Ok(r) => r,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && link.file_type().is_symlink() => {
            return Err(unusable(
                file,
                "is a link to a file that does not exist: not written through it",
            ))
        }
        Err(e) => return Err(io(file, "write")(e)),
    };
    if let Some(root) = inside {
        let root = std::fs::canonicalize(root).map_err(io(file, "write"))?;
        if !real.starts_with(&root) {
            return Err(unusable(
                file,
                "leads outside the folder served (through a link): not written",
            ));
        }
    }
    Ok(real)
}

/// Removes the temporaries an earlier writer of `real` left when it was killed (called with
/// the file's lock held, so no live writer's temporary is among them).
fn remove_stale(real: &Path) {
    let (Some(dir), Some(name)) = (real.parent(), real.file_name()) else {
        return;
    };
    let prefix = format!(".{}.", name.to_string_lossy());
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let n = e.file_name();
        let n = n.to_string_lossy();
        if n.starts_with(&prefix) && n.ends_with(TEMP_SUFFIX) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// The suffix of a write's temporary file.
pub const TEMP_SUFFIX: &str = ".pim-tmp";

/// Writes `text` over the regular file `real`, whose open, locked handle is `locked`: a
/// temporary beside it, synced, given the file's mode and owner, renamed over it, the folder
/// synced.
fn replace(file: &str, real: &Path, locked: &File, text: &str) -> Result<(), StoreError> {
    let meta = locked.metadata().map_err(io(file, "write"))?;
    let dir = real.parent().unwrap_or(Path::new("."));
    let name = real
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    remove_stale(real);
    let mut tmp = tempfile::Builder::new()
        .prefix(&format!(".{name}."))
        .suffix(TEMP_SUFFIX)
        .tempfile_in(dir)
        .map_err(io(file, "write"))?;
    tmp.write_all(text.as_bytes()).map_err(io(file, "write"))?;
    tmp.as_file().sync_all().map_err(io(file, "write"))?;
    let perms = std::fs::Permissions::from_mode(meta.mode() & 0o7777);
    tmp.as_file()
        .set_permissions(perms)
        .map_err(io(file, "write"))?;
    // The owner is kept where the process may give it (root editing another's file); where it
    // may not, the file becomes the writer's, as any editor's save does.
    let _ = std::os::unix::fs::fchown(tmp.as_file(), Some(meta.uid()), Some(meta.gid()));
    tmp.persist(real).map_err(|e| io(file, "write")(e.error))?;
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// Opens the real file, takes its exclusive lock and makes sure the path still names the file
/// locked (a writer may have renamed a new file over it meanwhile: then the lock is taken
/// again on that one).
fn lock(file: &str, real: &Path, max_bytes: u64) -> Result<File, StoreError> {
    loop {
        let f = open_regular(file, real, max_bytes)?;
        f.lock().map_err(io(file, "write"))?;
        let held = f.metadata().map_err(io(file, "write"))?;
        match std::fs::metadata(real) {
            Ok(now) if now.ino() == held.ino() && now.dev() == held.dev() => return Ok(f),
            Ok(_) => continue,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
            Err(e) => return Err(io(file, "write")(e)),
        }
    }
}

/// Reads the case file at `path`, lets `edit` make the new text from the current one, checks
/// it as `pim fit` does and writes it (see the crate's documentation), all under the file's
/// lock: no other writer changes the file between the read and the write. With
/// `options.expected`, the file must still be that version. Returns the text written and its
/// version.
///
/// # Errors
/// [`StoreError::Conflict`] when the file is not the version expected; what `edit` refuses
/// (as [`StoreError::Refused`]); [`StoreError::Refused`] for an edited text `pim fit`
/// refuses; [`StoreError::Unusable`], [`StoreError::Missing`] or [`StoreError::Io`] for the
/// file itself. Nothing is written on any error.
pub fn update<E: std::fmt::Display>(
    path: &Path,
    options: &WriteOptions<'_>,
    edit: impl FnOnce(&Stored) -> Result<String, E>,
) -> Result<Stored, StoreError> {
    let shown = path.display().to_string();
    let file = options.name.unwrap_or(&shown);
    let real = real_target(file, path, options.inside)?;
    let meta = std::fs::metadata(&real).map_err(io(file, "write"))?;
    if meta.is_file() && meta.mode() & 0o222 == 0 {
        return Err(unusable(
            file,
            format!(
                "is read-only (mode {:04o}): not written; make it writable (chmod u+w) to save \
                 into it",
                meta.mode() & 0o7777
            ),
        ));
    }
    let mut locked = lock(file, &real, MAX_CASE_BYTES)?;
    let current = read_open(file, &mut locked, MAX_CASE_BYTES)?;
    let text = edited(file, &current, options.expected, edit)?;
    if text != current.text {
        replace(file, &real, &locked, &text)?;
    }
    drop(locked);
    let version = Version::of(&text);
    Ok(Stored { text, version })
}

/// What [`update`] would write, without writing it (`pim set --dry-run`): the file read, its
/// version checked against `options.expected`, `edit` applied and the result checked as `pim
/// fit` checks a case; no lock is taken.
///
/// # Errors
/// As [`update`], but for those of the write itself.
pub fn preview<E: std::fmt::Display>(
    path: &Path,
    options: &WriteOptions<'_>,
    edit: impl FnOnce(&Stored) -> Result<String, E>,
) -> Result<Stored, StoreError> {
    let shown = path.display().to_string();
    let file = options.name.unwrap_or(&shown);
    let mut f = open_regular(file, path, MAX_CASE_BYTES)?;
    let current = read_open(file, &mut f, MAX_CASE_BYTES)?;
    let text = edited(file, &current, options.expected, edit)?;
    let version = Version::of(&text);
    Ok(Stored { text, version })
}

/// The text `edit` makes of `current`: refused when `current` is not the version `expected`,
/// when `edit` refuses, or when `pim fit` would refuse the result.
fn edited<E: std::fmt::Display>(
    file: &str,
    current: &Stored,
    expected: Option<&str>,
    edit: impl FnOnce(&Stored) -> Result<String, E>,
) -> Result<String, StoreError> {
    if let Some(expected) = expected {
        if !current.version.matches(expected) {
            return Err(StoreError::Conflict {
                file: file.to_string(),
                expected: expected.to_string(),
                current: current.clone(),
            });
        }
    }
    let text = edit(current).map_err(|e| StoreError::Refused(e.to_string()))?;
    check(file, &text)?;
    Ok(text)
}

/// Writes `text` over the case file at `path` (which must exist): [`update`] with the new
/// text whatever the current one is.
///
/// # Errors
/// As [`update`].
pub fn write(path: &Path, text: &str, options: &WriteOptions<'_>) -> Result<Stored, StoreError> {
    update(path, options, |_| {
        Ok::<_, std::convert::Infallible>(text.to_string())
    })
}

/// Checks a case's text as `pim fit` does ([`pim_studies::check::check_text`]).
///
/// # Errors
/// [`StoreError::Refused`] with `pim fit`'s message.
pub fn check(file: &str, text: &str) -> Result<(), StoreError> {
    if text.len() as u64 > MAX_CASE_BYTES {
        return Err(unusable(
            file,
            format!("the text is larger than the {MAX_CASE_BYTES} bytes a case file may be"),
        ));
    }
    pim_studies::check::check_text(file, text)
        .map(|_| ())
        .map_err(|e| StoreError::Refused(e.to_string()))
}

/// Creates the case file at `path` with `text`: checked as `pim fit` reads it, written to a
/// temporary beside it and linked into place only if no file of that name exists (a file made
/// meanwhile by another writer is never replaced), the folder synced. With `options.inside`,
/// the folder must lie inside it. `options.expected` is not used (there is no version yet).
///
/// # Errors
/// [`StoreError::Refused`] for a text `pim fit` refuses; [`StoreError::Unusable`] for a name
/// that exists already or a folder outside `options.inside`; [`StoreError::Io`]. Nothing is
/// written on any error.
pub fn create(path: &Path, text: &str, options: &WriteOptions<'_>) -> Result<Stored, StoreError> {
    let shown = path.display().to_string();
    let file = options.name.unwrap_or(&shown);
    check(file, text)?;
    let exists = || {
        unusable(
            file,
            "exists already: open it, or give the new case another name",
        )
    };
    if std::fs::symlink_metadata(path).is_ok() {
        return Err(exists());
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if let Some(root) = options.inside {
        let root = std::fs::canonicalize(root).map_err(io(file, "write"))?;
        let real = std::fs::canonicalize(dir).map_err(io(file, "write"))?;
        if !real.starts_with(&root) {
            return Err(unusable(
                file,
                "lies outside the folder served: not written",
            ));
        }
    }
    let mut tmp = tempfile::Builder::new()
        .prefix(".new.")
        .suffix(TEMP_SUFFIX)
        .tempfile_in(dir)
        .map_err(io(file, "write"))?;
    tmp.write_all(text.as_bytes()).map_err(io(file, "write"))?;
    tmp.as_file().sync_all().map_err(io(file, "write"))?;
    tmp.as_file()
        .set_permissions(std::fs::Permissions::from_mode(0o644))
        .map_err(io(file, "write"))?;
    tmp.persist_noclobber(path).map_err(|e| {
        if e.error.kind() == std::io::ErrorKind::AlreadyExists {
            exists()
        } else {
            io(file, "write")(e.error)
        }
    })?;
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(Stored {
        text: text.to_string(),
        version: Version::of(text),
    })
}
