//! Temporary run folders (`$TMPDIR/<prefix>-<pid>-<n>`): made per server start, removed when
//! the server is stopped, and swept when the process that made them is gone (a killed test
//! run, a crash), so a machine that starts thousands of servers does not fill its temp dir.

use std::path::{Path, PathBuf};

/// Remove `<prefix>-<pid>-…` folders in `parent` whose process `pid` no longer runs. Folders
/// of running processes, other names and anything unreadable are left alone.
pub fn remove_orphaned_dirs(parent: &Path, prefix: &str) -> usize {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(|n| owner_pid(n, prefix)) else {
            continue;
        };
        if pid != std::process::id() && !process_runs(pid) && entry.path().is_dir() {
            removed += usize::from(std::fs::remove_dir_all(entry.path()).is_ok());
        }
    }
    removed
}

/// The pid in `<prefix>-<pid>-<rest>`.
fn owner_pid(name: &str, prefix: &str) -> Option<u32> {
    let rest = name.strip_prefix(prefix)?.strip_prefix('-')?;
    let (pid, tail) = rest.split_once('-')?;
    (!tail.is_empty()).then_some(())?;
    pid.parse().ok()
}

fn process_runs(pid: u32) -> bool {
    let Ok(pid) = i32::try_from(pid) else {
        return false;
    };
    // SAFETY: signal 0 only checks that the process exists; nothing is sent.
    let alive = unsafe { libc::kill(pid, 0) } == 0;
    alive || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// A fresh `<prefix>-<this pid>-<n>` folder in the temp dir, after sweeping orphans.
pub fn fresh_dir(prefix: &str) -> std::io::Result<PathBuf> {
    use std::sync::atomic::{AtomicU32, Ordering};
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let parent = std::env::temp_dir();
    remove_orphaned_dirs(&parent, prefix);
    let dir = parent.join(format!(
        "{prefix}-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir)?;
    Ok(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_owner_pid_is_read_from_the_folder_name_only_with_the_prefix() {
        assert_eq!(owner_pid("libero-server-123-4", "libero-server"), Some(123));
        assert_eq!(owner_pid("libero-server-123-", "libero-server"), None);
        assert_eq!(owner_pid("libero-serverx-123-4", "libero-server"), None);
        assert_eq!(owner_pid("libero-server-abc-4", "libero-server"), None);
        assert_eq!(owner_pid("libero-data-9-keeper", "libero-data"), Some(9));
    }

    #[test]
    fn folders_of_gone_processes_are_swept_and_those_of_running_ones_kept() {
        let parent = std::env::temp_dir().join(format!("scratch-sweep-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&parent);
        // A pid above the kernel's maximum (4,194,304) cannot run.
        let gone = parent.join("run-4999999-0");
        let mine = parent.join(format!("run-{}-0", std::process::id()));
        let parent_pid = parent.join(format!("run-{}-0", std::os::unix::process::parent_id()));
        let other = parent.join("keep-4999999-0");
        for d in [&gone, &mine, &parent_pid, &other] {
            std::fs::create_dir_all(d.join("sub")).unwrap();
            std::fs::write(d.join("sub/log"), "x").unwrap();
        }
        assert_eq!(remove_orphaned_dirs(&parent, "run"), 1);
        assert!(!gone.exists());
        assert!(mine.exists() && parent_pid.exists() && other.exists());
        std::fs::remove_dir_all(&parent).unwrap();
    }
}
