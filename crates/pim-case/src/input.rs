//! Reading an input's text with a size limit that holds for any source. The caller opens the
//! file (this crate does no file-system I/O) and passes its metadata and reader; devices,
//! pipes and sockets are refused before they are read (a FIFO would wait for a writer,
//! `/dev/zero` never ends), and the read stops one byte past the limit.

use crate::error::{InputError, Result};
use std::io::Read;

/// Refuses what is not a regular file, naming it.
pub fn check_regular(name: &str, meta: &std::fs::Metadata) -> Result<()> {
    if meta.is_dir() {
        return Err(InputError::new(name, "is a directory, expected a file"));
    }
    if !meta.is_file() {
        return Err(InputError::new(
            name,
            "is not a regular file (a device, pipe or socket); give a file",
        ));
    }
    Ok(())
}

/// Refuses what is not a regular file, and a file larger than `max_bytes` by its own account
/// (the read is capped anyway: [`read_text`]).
pub fn check_file(name: &str, meta: &std::fs::Metadata, max_bytes: u64) -> Result<()> {
    check_regular(name, meta)?;
    if meta.len() > max_bytes {
        return Err(InputError::new(
            name,
            format!(
                "is {} bytes, larger than the {max_bytes} bytes accepted for this kind of file",
                meta.len()
            ),
        ));
    }
    Ok(())
}

/// The UTF-8 text of `reader`, at most `max_bytes` long.
pub fn read_text(name: &str, reader: impl Read, max_bytes: u64) -> Result<String> {
    let mut bytes = Vec::new();
    reader
        .take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| InputError::new(name, format!("cannot read: {e}")))?;
    if bytes.len() as u64 > max_bytes {
        return Err(InputError::new(
            name,
            format!("is larger than the {max_bytes} bytes accepted for this kind of file"),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        InputError::new(
            name,
            format!("is not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_endless_source_is_cut_at_the_limit() {
        let endless = std::io::repeat(b'a');
        let err = read_text("endless", endless, 1000).unwrap_err();
        assert!(
            err.message.contains("larger than the 1000 bytes"),
            "{}",
            err.message
        );
        assert_eq!(read_text("t", &b"abc"[..], 3).unwrap(), "abc");
        assert!(read_text("t", &[0xffu8, 0xfe][..], 10).is_err());
    }
}
