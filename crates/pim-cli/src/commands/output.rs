//! Output folders (`--out DIR`) written as a whole.
//!
//! A run writes into a staging folder beside `DIR` and puts it in place only when everything is
//! written: an earlier run's folder stays intact until then and is replaced as a whole, so a
//! folder never mixes two runs' files, and a run that fails half-way (a full disk, an error)
//! leaves the earlier results as they were and no half-written file under a final name. A
//! folder is replaced only when it is empty or was written by `pim` (it holds the marker file
//! `.pim-output`, or only files that pim writes); any other non-empty folder is refused, so
//! `--out` can never delete a user's files.

use crate::error::Failure;
use crate::inputs::io_reason;
use anyhow::Result;
use std::path::{Path, PathBuf};

/// The marker file of a folder written by `pim`.
const MARKER: &str = ".pim-output";

/// Every file name `pim` writes into an output folder: a folder holding only these (from a
/// version before the marker) is pim's too.
const OUTPUT_FILES: [&str; 28] = [
    "records.csv",
    "records.json",
    "records.jsonl",
    "velocity_errors.csv",
    "summary.txt",
    "compare_costs.txt",
    "brach1984.txt",
    "models.txt",
    "cost.svg",
    "coefficients.svg",
    "delta_v.svg",
    "separation.svg",
    "models.svg",
    "result.json",
    "report.md",
    "report.html",
    "momentum.svg",
    "diagram.svg",
    "uncertainty.json",
    "uncertainty.txt",
    "histograms.svg",
    "speeds.svg",
    "tornado.svg",
    "predict_dv.json",
    "predict_dv.txt",
    "predict_dv.svg",
    "sensitivity.json",
    "sensitivity.txt",
];

/// An output folder being written.
pub struct OutDir {
    target: PathBuf,
    stage: PathBuf,
    committed: bool,
}

pub(crate) fn io_failure(path: &Path, what: &str, e: &std::io::Error) -> Failure {
    Failure::Output(format!("{}: {what}: {}", path.display(), io_reason(e)))
}

impl OutDir {
    /// Starts writing the folder `dir`: checks that it may be replaced and creates the staging
    /// folder beside it.
    pub fn create(dir: &Path) -> Result<Self> {
        if dir.exists() {
            if !dir.is_dir() {
                return Err(Failure::Output(format!(
                    "{}: exists and is not a folder; give a folder for --out",
                    dir.display()
                ))
                .into());
            }
            let names: Vec<String> = std::fs::read_dir(dir)
                .map_err(|e| io_failure(dir, "cannot read", &e))?
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect();
            let ours = dir.join(MARKER).is_file()
                || names.iter().all(|n| OUTPUT_FILES.contains(&n.as_str()));
            if !ours {
                return Err(Failure::Output(format!(
                    "{}: holds files that pim did not write; give a new or empty folder (pim \
                     replaces only its own output folders)",
                    dir.display()
                ))
                .into());
            }
        }
        let name = dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "out".to_string());
        let parent = dir
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        // Failures name the folder given (and the part of it that failed), never the staging
        // folder, which the user did not write and never sees.
        std::fs::create_dir_all(parent).map_err(|e| {
            let what = if parent.is_file() {
                format!("cannot create the folder: {} is a file", parent.display())
            } else {
                format!("cannot create the folder {}", parent.display())
            };
            io_failure(dir, &what, &e)
        })?;
        let stage = parent.join(format!(".{name}.pim-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&stage);
        std::fs::create_dir(&stage).map_err(|e| {
            io_failure(
                dir,
                &format!("cannot write in {} to stage the folder", parent.display()),
                &e,
            )
        })?;
        let out = OutDir {
            target: dir.to_path_buf(),
            stage,
            committed: false,
        };
        out.write(
            MARKER,
            "written by pim; the whole folder is replaced by the next run\n",
        )?;
        Ok(out)
    }

    /// The folder's final path (for messages).
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Where the file `name` is written until the folder is put in place.
    pub fn file(&self, name: &str) -> PathBuf {
        self.stage.join(name)
    }

    /// The file `name` as messages name it: its final path in the folder given.
    pub fn shown(&self, name: &str) -> PathBuf {
        self.target.join(name)
    }

    /// Writes the file `name`; a failure names the file by its final path.
    pub fn write(&self, name: &str, text: &str) -> Result<()> {
        self.write_bytes(name, text.as_bytes())
    }

    /// Writes the file `name` of `bytes` (a drawing); a failure names the file by its final
    /// path.
    pub fn write_bytes(&self, name: &str, bytes: &[u8]) -> Result<()> {
        std::fs::write(self.file(name), bytes)
            .map_err(|e| io_failure(&self.target.join(name), "cannot write", &e).into())
    }

    /// Puts the folder in place, replacing an earlier run's as a whole.
    pub fn commit(mut self) -> Result<()> {
        let old = PathBuf::from(format!("{}.old", self.stage.display()));
        let had_old = self.target.exists();
        if had_old {
            std::fs::rename(&self.target, &old)
                .map_err(|e| io_failure(&self.target, "cannot replace", &e))?;
        }
        if let Err(e) = std::fs::rename(&self.stage, &self.target) {
            if had_old {
                let _ = std::fs::rename(&old, &self.target);
            }
            return Err(io_failure(&self.target, "cannot put in place", &e).into());
        }
        self.committed = true;
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
        }
        Ok(())
    }
}

impl Drop for OutDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.stage);
        }
    }
}
