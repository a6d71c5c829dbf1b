//! Finding and reading data files at a cost bounded whatever lies in the folders: a size limit
//! checked before reading, text only, a leading byte-order mark dropped, and a folder walk that
//! enters every directory once and never leaves the tree it was given. Hot reload runs this on
//! every edit, so a stray 50 MB file or a link loop must cost a refusal, not seconds and memory.

use crate::diagnostics::{Diagnostic, Report};
use std::collections::HashSet;
use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The largest data file read, in bytes. The biggest shipped file is a few KiB; anything near
/// this is not a hand-written tree, strategy, scenario or parameter file.
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// The byte-order mark some editors write at the start of UTF-8 files.
const BOM: char = '\u{feff}';

/// Why a data file's text could not be had.
#[derive(Debug)]
pub enum ReadError {
    /// Gone between listing and reading (an editor's save by rename): not a problem to report.
    Missing,
    TooLarge {
        size: u64,
    },
    NotAFile,
    NotText {
        valid_up_to: usize,
    },
    Io(std::io::Error),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::Missing => f.write_str("does not exist"),
            ReadError::TooLarge { size } => write!(
                f,
                "is {size} bytes, over the limit of {MAX_FILE_BYTES} bytes (1 MiB) for data files; not read"
            ),
            ReadError::NotAFile => f.write_str("is not a regular file"),
            ReadError::NotText { valid_up_to } => write!(
                f,
                "is not UTF-8 text (invalid bytes at offset {valid_up_to}); a binary file?"
            ),
            ReadError::Io(error) => write!(f, "cannot be read: {error}"),
        }
    }
}

impl ReadError {
    /// The message naming the file, as diagnostics and logs show it.
    pub fn describe(&self, path: &Path) -> String {
        format!("{} {self}", path.display())
    }
}

/// The text of a data file, refused before reading when over [`MAX_FILE_BYTES`] or not a
/// regular file (a FIFO would block the reader forever), with a leading BOM removed.
pub fn read_text(path: &Path) -> Result<String, ReadError> {
    let io = |error: std::io::Error| match error.kind() {
        std::io::ErrorKind::NotFound => ReadError::Missing,
        _ => ReadError::Io(error),
    };
    let metadata = std::fs::metadata(path).map_err(io)?;
    if !metadata.is_file() {
        return Err(ReadError::NotAFile);
    }
    if metadata.len() > MAX_FILE_BYTES {
        return Err(ReadError::TooLarge {
            size: metadata.len(),
        });
    }
    // The file may grow between the check and the read: never take more than the limit.
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    std::fs::File::open(path)
        .map_err(io)?
        .take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(ReadError::TooLarge {
            size: bytes.len() as u64,
        });
    }
    match String::from_utf8(bytes) {
        Ok(text) => Ok(strip_bom_owned(text)),
        Err(error) => Err(ReadError::NotText {
            valid_up_to: error.utf8_error().valid_up_to(),
        }),
    }
}

/// `text` without a leading byte-order mark: invisible in an editor, and no RON value.
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix(BOM).unwrap_or(text)
}

pub(crate) fn strip_bom_owned(mut text: String) -> String {
    if text.starts_with(BOM) {
        text.drain(..BOM.len_utf8());
    }
    text
}

/// A file that makes its folder a team of its own (`formations/simspark/` beside
/// `formations/`): a walk from above does not enter that folder.
pub const TEAM_FILE: &str = "team.ron";

/// `.ron` files under the given paths (folders searched recursively, but not into a subfolder
/// holding its own [`TEAM_FILE`]: that is another team's set), sorted so results do not
/// depend on directory order. Each directory is entered once, by its real path: a link back up
/// the tree (`self -> .`) or a loop of links adds nothing. Links that resolve outside the folder
/// they sit in, or not at all, are skipped with a warning. A file reached by two paths is
/// listed once, under the first path in sorted order.
pub fn ron_files(paths: &[PathBuf], report: &mut Report) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut visited = HashSet::new();
    for path in paths {
        if path.is_dir() {
            match path.canonicalize() {
                Ok(root) => {
                    visited.insert(root.clone());
                    let mut walk = Walk {
                        root: &root,
                        shown_root: path,
                        visited: &mut visited,
                        out: &mut files,
                        report,
                    };
                    walk.dir(path);
                }
                Err(error) => report.push(Diagnostic::error(
                    "io",
                    format!("cannot read directory {}: {error}", path.display()),
                )),
            }
        } else if path.exists() {
            files.push(path.clone());
        } else {
            report.push(Diagnostic::error(
                "io",
                format!("{} does not exist", path.display()),
            ));
        }
    }
    files.sort();
    files.dedup();
    let mut real_seen = HashSet::new();
    files.retain(|file| real_seen.insert(file.canonicalize().unwrap_or_else(|_| file.clone())));
    files
}

struct Walk<'a> {
    /// The real path of the folder being walked: nothing outside it is entered.
    root: &'a Path,
    shown_root: &'a Path,
    /// Real paths of every directory entered in this listing, across all roots.
    visited: &'a mut HashSet<PathBuf>,
    out: &'a mut Vec<PathBuf>,
    report: &'a mut Report,
}

impl Walk<'_> {
    fn dir(&mut self, dir: &Path) {
        let entries = match std::fs::read_dir(dir) {
            Ok(entries) => entries,
            Err(error) => {
                self.report.push(Diagnostic::error(
                    "io",
                    format!("cannot read directory {}: {error}", dir.display()),
                ));
                return;
            }
        };
        let mut entries: Vec<_> = entries.flatten().collect();
        // Which of two paths to one directory is entered must not depend on directory order.
        entries.sort_by_key(|entry| entry.file_name());
        for entry in entries {
            let path = entry.path();
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            let is_dir = if kind.is_symlink() {
                match self.follow(&path) {
                    Some(is_dir) => is_dir,
                    None => continue,
                }
            } else {
                kind.is_dir()
            };
            if is_dir {
                if path.join(TEAM_FILE).is_file() {
                    continue;
                }
                let real = path.canonicalize().unwrap_or_else(|_| path.clone());
                if self.visited.insert(real) {
                    self.dir(&path);
                }
            } else if path.extension().is_some_and(|e| e == "ron") {
                self.out.push(path);
            }
        }
    }

    /// Whether the link at `path` leads to a directory; `None` when it is skipped.
    fn follow(&mut self, path: &Path) -> Option<bool> {
        let real = match path.canonicalize() {
            Ok(real) => real,
            Err(error) => {
                self.report.push(Diagnostic::warning(
                    "link",
                    format!(
                        "skipped link {}: it cannot be followed ({error})",
                        path.display()
                    ),
                ));
                return None;
            }
        };
        if !real.starts_with(self.root) {
            self.report.push(Diagnostic::warning(
                "link",
                format!(
                    "skipped link {}: it leads to {}, outside {}",
                    path.display(),
                    real.display(),
                    self.shown_root.display()
                ),
            ));
            return None;
        }
        Some(real.is_dir())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    #[test]
    fn a_file_over_the_limit_is_refused_before_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("huge.ron");
        // Sparse: 50 MB on paper, nothing on disk, and reading it would take real time.
        std::fs::File::create(&path)
            .unwrap()
            .set_len(50 << 20)
            .unwrap();
        let start = Instant::now();
        let error = read_text(&path).unwrap_err();
        assert!(start.elapsed() < Duration::from_millis(100));
        assert!(matches!(error, ReadError::TooLarge { size } if size == 50 << 20));
        let message = error.describe(&path);
        assert!(message.contains("huge.ron") && message.contains(&MAX_FILE_BYTES.to_string()));
        std::fs::write(&path, "x".repeat(MAX_FILE_BYTES as usize)).unwrap();
        assert_eq!(read_text(&path).unwrap().len(), MAX_FILE_BYTES as usize);
    }

    #[test]
    fn a_leading_bom_is_dropped_and_binary_is_not_text() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.ron");
        std::fs::write(&path, "\u{feff}Team()").unwrap();
        assert_eq!(read_text(&path).unwrap(), "Team()");
        assert_eq!(strip_bom("\u{feff}x\u{feff}"), "x\u{feff}");
        std::fs::write(&path, [0x52, 0x00, 0xff, 0xfe, 0x13]).unwrap();
        assert!(matches!(
            read_text(&path),
            Err(ReadError::NotText { valid_up_to: 2 })
        ));
        assert!(matches!(
            read_text(&dir.path().join("gone.ron")),
            Err(ReadError::Missing)
        ));
        assert!(matches!(read_text(dir.path()), Err(ReadError::NotAFile)));
    }

    #[cfg(unix)]
    #[test]
    fn a_subfolder_with_its_own_team_file_is_another_team() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        std::fs::create_dir_all(root.join("nao")).unwrap();
        std::fs::create_dir_all(root.join("more")).unwrap();
        for file in [
            "team.ron",
            "attack.ron",
            "nao/team.ron",
            "nao/attack.ron",
            "more/x.ron",
        ] {
            std::fs::write(root.join(file), "Team()").unwrap();
        }
        let mut report = Report::default();
        let names = |files: Vec<PathBuf>| -> Vec<String> {
            files
                .iter()
                .map(|f| f.strip_prefix(root).unwrap().display().to_string())
                .collect()
        };
        let files = ron_files(&[root.to_path_buf()], &mut report);
        assert_eq!(names(files), ["attack.ron", "more/x.ron", "team.ron"]);
        // Named itself, the team's folder is walked.
        let files = ron_files(&[root.join("nao")], &mut report);
        assert_eq!(names(files), ["nao/attack.ron", "nao/team.ron"]);
    }

    #[test]
    fn links_are_followed_once_and_never_out_of_the_tree() {
        use std::os::unix::fs::symlink;
        let outer = tempfile::tempdir().unwrap();
        std::fs::write(outer.path().join("outside.ron"), "").unwrap();
        let root = outer.path().join("behaviors");
        std::fs::create_dir_all(root.join("sub")).unwrap();
        std::fs::write(root.join("a.ron"), "").unwrap();
        std::fs::write(root.join("sub/b.ron"), "").unwrap();
        symlink("b_link", root.join("a_link")).unwrap();
        symlink("a_link", root.join("b_link")).unwrap();
        symlink(".", root.join("self")).unwrap();
        symlink("..", root.join("up")).unwrap();
        symlink("sub", root.join("sub_again")).unwrap();
        symlink("a.ron", root.join("z.ron")).unwrap();
        let mut report = Report::default();
        let start = Instant::now();
        let files = ron_files(std::slice::from_ref(&root), &mut report);
        assert!(start.elapsed() < Duration::from_secs(1));
        assert_eq!(files, vec![root.join("a.ron"), root.join("sub/b.ron")]);
        let messages: Vec<&str> = report
            .diagnostics
            .iter()
            .map(|d| d.message.as_str())
            .collect();
        assert_eq!(report.error_count(), 0, "{messages:?}");
        // The loop's two links cannot be followed; `up` leads out: one warning each.
        assert_eq!(report.warning_count(), 3, "{messages:?}");
        assert_eq!(messages.iter().filter(|m| m.contains("outside")).count(), 1);
    }
}
