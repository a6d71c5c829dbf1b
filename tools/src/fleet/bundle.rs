//! The files a job needs, in one folder: this `libero` binary and the data it reads.

use std::path::{Path, PathBuf};

/// The repository's folders every job may read, relative to the project root.
const SHIPPED: [&str; 5] = [
    "behaviors",
    "formations",
    "engine/skills/params",
    "scenarios",
    "tools/teams",
];

/// A folder laid out like the repository (jobs run with `LIBERO_HOME` set to it), holding a
/// copy of the running binary as `libero`. Removed when dropped.
pub struct Bundle {
    _scratch: tempfile::TempDir,
    root: PathBuf,
}

impl Bundle {
    /// The running binary, the repository's data folders, and each `(source, name)` of
    /// `extra` copied to `name` inside (a team folder, say, as `teams/home`).
    pub fn stage(extra: &[(&Path, &str)]) -> Result<Bundle, String> {
        let scratch = tempfile::Builder::new()
            .prefix("libero-bundle-")
            .tempdir()
            .map_err(|e| format!("cannot make a bundle folder: {e}"))?;
        let root = scratch.path().join("bundle");
        std::fs::create_dir_all(&root).map_err(|e| format!("{}: {e}", root.display()))?;
        let exe = std::env::current_exe().map_err(|e| format!("cannot find this binary: {e}"))?;
        copy_file(&exe, &root.join("libero"))?;
        let project = libero_server::venv::project_root();
        for name in SHIPPED {
            let from = project.join(name);
            if from.is_dir() {
                copy_tree(&from, &root.join(name))?;
            }
        }
        for (from, name) in extra {
            if Path::new(name).is_absolute() || name.split('/').any(|part| part == "..") {
                return Err(format!(
                    "bundle entry `{name}` must be a relative path inside"
                ));
            }
            if from.is_dir() {
                copy_tree(from, &root.join(name))?;
            } else {
                copy_file(from, &root.join(name))?;
            }
        }
        Ok(Bundle {
            _scratch: scratch,
            root,
        })
    }

    pub fn root(&self) -> &Path {
        &self.root
    }

    /// A scratch folder beside the bundle (not shipped with it).
    pub fn scratch(&self) -> &Path {
        self._scratch.path()
    }
}

fn copy_file(from: &Path, to: &Path) -> Result<(), String> {
    if let Some(parent) = to.parent() {
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
    }
    std::fs::copy(from, to)
        .map(|_| ())
        .map_err(|e| format!("cannot copy {} into the bundle: {e}", from.display()))
}

/// Regular files and folders only: a link could point anywhere, so it is left out.
fn copy_tree(from: &Path, to: &Path) -> Result<(), String> {
    std::fs::create_dir_all(to).map_err(|e| format!("{}: {e}", to.display()))?;
    let entries =
        std::fs::read_dir(from).map_err(|e| format!("cannot read {}: {e}", from.display()))?;
    for entry in entries {
        let entry = entry.map_err(|e| format!("{}: {e}", from.display()))?;
        let kind = entry
            .file_type()
            .map_err(|e| format!("{}: {e}", entry.path().display()))?;
        let target = to.join(entry.file_name());
        if kind.is_dir() {
            copy_tree(&entry.path(), &target)?;
        } else if kind.is_file() {
            copy_file(&entry.path(), &target)?;
        } else {
            log::warn!(
                "bundle: {} left out (not a plain file)",
                entry.path().display()
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_the_binary_the_data_and_the_extras_but_no_links() {
        let team = tempfile::tempdir().unwrap();
        std::fs::create_dir(team.path().join("behaviors")).unwrap();
        std::fs::write(team.path().join("behaviors/a.ron"), "x").unwrap();
        std::os::unix::fs::symlink("/etc/passwd", team.path().join("behaviors/link.ron")).unwrap();
        let bundle = Bundle::stage(&[(team.path(), "teams/home")]).unwrap();
        let root = bundle.root();
        assert!(root.join("libero").is_file());
        assert!(root.join("behaviors/field_player.ron").is_file());
        assert!(root.join("formations").is_dir());
        assert!(root.join("teams/home/behaviors/a.ron").is_file());
        assert!(!root.join("teams/home/behaviors/link.ron").exists());
        assert!(Bundle::stage(&[(team.path(), "../out")]).is_err());
    }
}
