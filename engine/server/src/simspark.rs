//! SimSpark rcssserver3d, the thesis's server: built from source into a per-user cache and run
//! headless from a temporary folder.
//!
//! No package registry carries it, so [`ensure_simspark_installed`] builds spark and
//! rcssserver3d with `simspark/build.sh` into `<cache>/simspark-<hash>/prefix`, keyed by the
//! source's SHA-256 (a second call with the same source is instant; another source builds
//! beside it). The run side ([`run_files`]) writes the server's `rcssserver3d.rb` into the
//! run folder's `.simspark/`, where the server looks first when `HOME` points there, so the
//! user's home is never touched.

use crate::venv::project_root;
use crate::ServerError;
use sha2::{Digest, Sha256};
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The archive the tests build from when no source is named (beside the checkout).
pub const DEFAULT_ARCHIVE: &str = "../shared/simspark/SIMSPARK-f6934a6.tar.xz";

/// Debian packages the headless build needs (spark looks for SDL 1.2, not SDL 2).
pub const BUILD_PACKAGES: [&str; 17] = [
    "cmake",
    "g++",
    "make",
    "pkg-config",
    "ruby",
    "ruby-dev",
    "libode-dev",
    "libboost-dev",
    "libboost-thread-dev",
    "libboost-regex-dev",
    "libboost-system-dev",
    "libfreetype-dev",
    "libdevil-dev",
    "libsdl1.2-dev",
    "libgl-dev",
    "libglu1-mesa-dev",
    "libtbb-dev",
];

const BUILD_SCRIPT: &str = include_str!("../simspark/build.sh");

/// A built SimSpark.
#[derive(Debug, Clone)]
pub struct SimSparkInstall {
    pub prefix: PathBuf,
}

impl SimSparkInstall {
    pub fn server_program(&self) -> PathBuf {
        self.prefix.join("bin").join("rcssserver3d")
    }

    /// The server's installed `rcssserver3d.rb` (the template of the run folder's copy).
    pub fn config_script(&self) -> PathBuf {
        self.prefix
            .join("share")
            .join("rcssserver3d")
            .join("rcssserver3d.rb")
    }

    /// Library folders the program needs at run time (also in its RPATH; set for safety).
    pub fn library_path(&self) -> String {
        let lib = self.prefix.join("lib");
        format!(
            "{}:{}",
            lib.join("simspark").display(),
            lib.join("rcssserver3d").display()
        )
    }
}

/// Where per-user builds live: `LIBERO_CACHE`, else `$XDG_CACHE_HOME/libero`, else
/// `~/.cache/libero` — never inside the checkout.
pub fn cache_root() -> PathBuf {
    if let Some(dir) = std::env::var_os("LIBERO_CACHE") {
        return PathBuf::from(dir);
    }
    if let Some(dir) = std::env::var_os("XDG_CACHE_HOME") {
        return PathBuf::from(dir).join("libero");
    }
    let home = std::env::var_os("HOME").map_or_else(std::env::temp_dir, PathBuf::from);
    home.join(".cache").join("libero")
}

/// The source a build without `--source` uses: `LIBERO_SIMSPARK_SOURCE`, else the archive
/// beside the checkout.
pub fn default_source() -> PathBuf {
    std::env::var_os("LIBERO_SIMSPARK_SOURCE")
        .map(PathBuf::from)
        .unwrap_or_else(|| project_root().join(DEFAULT_ARCHIVE))
}

/// Where a build of `source` goes, without building it: `None` when the source cannot be read.
pub fn install_dir_for(source: &Path) -> Result<PathBuf, ServerError> {
    Ok(cache_root().join(format!("simspark-{}", &source_hash(source)?[..16])))
}

/// The installed SimSpark for `source` (default: [`default_source`]), building it first if this
/// source was never built here. Safe to call from many processes: they take turns on a lock
/// file and all but the first find it done.
pub fn ensure_simspark_installed(source: Option<&Path>) -> Result<SimSparkInstall, ServerError> {
    let source = source.map_or_else(default_source, Path::to_path_buf);
    if !source.exists() {
        return Err(ServerError::SimSpark(format!(
            "no SimSpark source at {}: pass --source with a clone (holding spark/ and rcssserver3d/) or its archive",
            source.display()
        )));
    }
    let dir = install_dir_for(&source)?;
    let install = SimSparkInstall {
        prefix: dir.join("prefix"),
    };
    let marker = dir.join("installed");
    if marker.exists() && install.server_program().exists() {
        return Ok(install);
    }
    std::fs::create_dir_all(&dir).map_err(|e| io(&dir, e))?;
    let lock_path = dir.join("lock");
    let lock = File::create(&lock_path).map_err(|e| io(&lock_path, e))?;
    lock.lock().map_err(|e| io(&lock_path, e))?;
    if marker.exists() && install.server_program().exists() {
        return Ok(install);
    }
    ensure_build_packages()?;
    let work = dir.join("work");
    if work.exists() {
        std::fs::remove_dir_all(&work).map_err(|e| io(&work, e))?;
    }
    std::fs::create_dir_all(&work).map_err(|e| io(&work, e))?;
    let tree = unpack(&source, &work)?;
    let log_path = dir.join("build.log");
    eprintln!(
        "building SimSpark from {} into {} (first use of this source only; about 20 min on 2 cores; log {})",
        source.display(),
        install.prefix.display(),
        log_path.display()
    );
    let log = File::create(&log_path).map_err(|e| io(&log_path, e))?;
    let err = log.try_clone().map_err(|e| io(&log_path, e))?;
    let jobs = std::thread::available_parallelism().map_or(2, |n| n.get());
    let status = Command::new("bash")
        .arg("-c")
        .arg(BUILD_SCRIPT)
        .env("SRC", &tree)
        .env("PREFIX", &install.prefix)
        .env("JOBS", jobs.to_string())
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(err)
        .status()
        .map_err(|e| io(Path::new("bash"), e))?;
    if !status.success() || !install.server_program().exists() {
        return Err(ServerError::SimSpark(format!(
            "the SimSpark build failed ({status}); {} ends with:\n{}",
            log_path.display(),
            tail(&log_path, 15)
        )));
    }
    File::create(&marker).map_err(|e| io(&marker, e))?;
    let _ = std::fs::remove_dir_all(&work);
    Ok(install)
}

/// SHA-256 of an archive's bytes, or of a source folder's `spark/` and `rcssserver3d/` files
/// (relative paths and contents, in name order; `build/` folders and `.git` left out).
pub fn source_hash(source: &Path) -> Result<String, ServerError> {
    let mut hasher = Sha256::new();
    if source.is_dir() {
        let mut files = Vec::new();
        for part in ["spark", "rcssserver3d"] {
            let root = source.join(part);
            if !root.is_dir() {
                return Err(ServerError::SimSpark(format!(
                    "{} has no {part}/ folder: a SimSpark source holds spark/ and rcssserver3d/ side by side",
                    source.display()
                )));
            }
            collect_files(&root, &mut files)?;
        }
        files.sort();
        for file in files {
            let rel = file.strip_prefix(source).unwrap_or(&file);
            hasher.update(rel.to_string_lossy().as_bytes());
            hasher.update([0]);
            hash_file(&file, &mut hasher)?;
        }
    } else {
        hash_file(source, &mut hasher)?;
    }
    Ok(hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

fn collect_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), ServerError> {
    for entry in std::fs::read_dir(dir).map_err(|e| io(dir, e))? {
        let entry = entry.map_err(|e| io(dir, e))?;
        let path = entry.path();
        // Links are not followed: a source tree holds none worth hashing, and a loop would
        // never end.
        let kind = entry.file_type().map_err(|e| io(&path, e))?;
        let name = entry.file_name();
        if kind.is_dir() {
            if name != "build" && name != ".git" {
                collect_files(&path, out)?;
            }
        } else if kind.is_file() {
            out.push(path);
        }
    }
    Ok(())
}

fn hash_file(path: &Path, hasher: &mut Sha256) -> Result<(), ServerError> {
    let mut file = File::open(path).map_err(|e| io(path, e))?;
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = file.read(&mut buf).map_err(|e| io(path, e))?;
        if n == 0 {
            return Ok(());
        }
        hasher.update(&buf[..n]);
    }
}

/// Copy or unpack the source into `work`; returns the folder holding spark/ and rcssserver3d/.
fn unpack(source: &Path, work: &Path) -> Result<PathBuf, ServerError> {
    let mut cmd = if source.is_dir() {
        let mut cmd = Command::new("cp");
        cmd.arg("-a")
            .arg(source.join("spark"))
            .arg(source.join("rcssserver3d"))
            .arg(work);
        cmd
    } else {
        let mut cmd = Command::new("tar");
        cmd.arg("-xf").arg(source).arg("-C").arg(work);
        cmd
    };
    let out = cmd.output().map_err(|e| io(source, e))?;
    if !out.status.success() {
        return Err(ServerError::SimSpark(format!(
            "could not unpack {}: {}",
            source.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    find_tree(work).ok_or_else(|| {
        ServerError::SimSpark(format!(
            "{} holds no spark/ and rcssserver3d/ side by side",
            source.display()
        ))
    })
}

/// `dir` itself or its one subfolder (an archive's top folder) when it holds both parts.
fn find_tree(dir: &Path) -> Option<PathBuf> {
    let holds = |d: &Path| d.join("spark").is_dir() && d.join("rcssserver3d").is_dir();
    if holds(dir) {
        return Some(dir.to_path_buf());
    }
    std::fs::read_dir(dir)
        .ok()?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.is_dir() && holds(p))
}

/// Install the missing build packages when we can (root on Debian), else say exactly how.
fn ensure_build_packages() -> Result<(), ServerError> {
    let Some(missing) = missing_packages() else {
        log::info!("no dpkg here: the build packages are not checked (see BUILD_PACKAGES)");
        return Ok(());
    };
    if missing.is_empty() {
        return Ok(());
    }
    let command = format!("apt-get install -y {}", missing.join(" "));
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        return Err(ServerError::SimSpark(format!(
            "the SimSpark build needs Debian packages that are missing; install them with\n  sudo {command}\nand run this again"
        )));
    }
    eprintln!("installing the SimSpark build packages: {command}");
    let install = |update_first: bool| {
        if update_first {
            let _ = Command::new("apt-get").args(["update", "-q"]).output();
        }
        Command::new("apt-get")
            .args(["install", "-y", "-q"])
            .args(&missing)
            .env("DEBIAN_FRONTEND", "noninteractive")
            .output()
    };
    // A stale package list refuses packages whose dependencies have moved on: update, retry.
    let out = match install(false) {
        Ok(out) if out.status.success() => out,
        _ => install(true).map_err(|e| io(Path::new("apt-get"), e))?,
    };
    if !out.status.success() {
        return Err(ServerError::SimSpark(format!(
            "`{command}` failed: {}",
            last_lines(&String::from_utf8_lossy(&out.stderr), 6)
        )));
    }
    Ok(())
}

/// The build packages dpkg does not report installed; `None` without dpkg.
fn missing_packages() -> Option<Vec<&'static str>> {
    let mut missing = Vec::new();
    for package in BUILD_PACKAGES {
        let out = Command::new("dpkg-query")
            .args(["-W", "-f=${Status}", package])
            .output()
            .ok()?;
        if !String::from_utf8_lossy(&out.stdout).contains("install ok installed") {
            missing.push(package);
        }
    }
    Some(missing)
}

/// How the run folder's server is configured.
#[derive(Debug, Clone, Copy)]
pub struct RunSettings {
    pub agent_port: u16,
    pub monitor_port: u16,
    pub sync: bool,
    pub realtime: bool,
}

/// Write the run folder's `.simspark/rcssserver3d.rb`: the installed script with our ports and
/// modes set before it sets the server up. Threading stays off (with Ruby 3 the threaded
/// server crashed when a monitor connected, and threaded agent control stalled at the 17th
/// agent: simspark.md §1.4).
pub fn run_files(
    install: &SimSparkInstall,
    run_dir: &Path,
    settings: RunSettings,
) -> Result<(), ServerError> {
    let template_path = install.config_script();
    let template = std::fs::read_to_string(&template_path).map_err(|e| io(&template_path, e))?;
    let script = configured_script(&template, settings);
    let dot = run_dir.join(".simspark");
    std::fs::create_dir_all(&dot).map_err(|e| io(&dot, e))?;
    let path = dot.join("rcssserver3d.rb");
    std::fs::write(&path, script).map_err(|e| io(&path, e))
}

/// The installed `rcssserver3d.rb` with `settings` in force. The real-time switch is the
/// script's own variable; the others are spark.rb's, read when `sparkSetupServer()` runs.
pub fn configured_script(template: &str, settings: RunSettings) -> String {
    let header = format!(
        "# Written by libero for this run.\n\
         $agentPort = {}\n$serverPort = {}\n$agentSyncMode = {}\n\
         $threadedAgentControl = false\n$serverMultiThreadedMode = false\n",
        settings.agent_port, settings.monitor_port, settings.sync
    );
    let body: String = template
        .lines()
        .map(|line| {
            if line.trim_start().starts_with("$enableRealTimeMode") {
                format!("$enableRealTimeMode = {}", settings.realtime)
            } else {
                line.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    format!("{header}{body}\n")
}

fn io(path: &Path, e: std::io::Error) -> ServerError {
    ServerError::Io(path.display().to_string(), e)
}

fn tail(path: &Path, n: usize) -> String {
    last_lines(&std::fs::read_to_string(path).unwrap_or_default(), n)
}

fn last_lines(text: &str, n: usize) -> String {
    let lines: Vec<&str> = text.lines().rev().take(n).collect();
    lines.into_iter().rev().collect::<Vec<_>>().join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_run_script_sets_ports_and_modes_before_the_setup() {
        let template = "# rcssserver3d.rb\n$enableRealTimeMode = true\nsparkSetupServer()\n";
        let script = configured_script(
            template,
            RunSettings {
                agent_port: 23100,
                monitor_port: 23200,
                sync: true,
                realtime: false,
            },
        );
        let setup = script.find("sparkSetupServer()").unwrap();
        for line in [
            "$agentPort = 23100",
            "$serverPort = 23200",
            "$agentSyncMode = true",
            "$threadedAgentControl = false",
            "$serverMultiThreadedMode = false",
            "$enableRealTimeMode = false",
        ] {
            let at = script
                .find(line)
                .unwrap_or_else(|| panic!("{line} missing:\n{script}"));
            assert!(at < setup, "{line} comes after the setup");
        }
        assert!(!script.contains("$enableRealTimeMode = true"));
    }

    #[test]
    fn a_folder_source_is_keyed_by_its_files_and_needs_both_parts() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        assert!(matches!(source_hash(root), Err(ServerError::SimSpark(_))));
        std::fs::create_dir_all(root.join("spark/lib")).unwrap();
        std::fs::create_dir_all(root.join("rcssserver3d/build")).unwrap();
        std::fs::write(root.join("spark/lib/a.cpp"), "int a;").unwrap();
        std::fs::write(root.join("rcssserver3d/CMakeLists.txt"), "project(x)").unwrap();
        let first = source_hash(root).unwrap();
        // A build folder's output does not change the key; a source edit does.
        std::fs::write(root.join("rcssserver3d/build/out.o"), "junk").unwrap();
        assert_eq!(source_hash(root).unwrap(), first);
        std::fs::write(root.join("spark/lib/a.cpp"), "int b;").unwrap();
        assert_ne!(source_hash(root).unwrap(), first);
        assert_eq!(find_tree(root).as_deref(), Some(root));
    }

    #[test]
    fn a_missing_or_partial_source_is_refused_with_what_to_pass() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nowhere.tar.xz");
        let e = ensure_simspark_installed(Some(&missing))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--source") && e.contains("nowhere.tar.xz"),
            "{e}"
        );
        // A folder without rcssserver3d/ is named as such before anything is built.
        std::fs::create_dir_all(dir.path().join("spark")).unwrap();
        let e = ensure_simspark_installed(Some(dir.path()))
            .unwrap_err()
            .to_string();
        assert!(e.contains("rcssserver3d/"), "{e}");
    }

    #[test]
    fn an_archive_is_keyed_by_its_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.tar.xz");
        std::fs::write(&a, b"archive one").unwrap();
        let key = source_hash(&a).unwrap();
        assert_eq!(key.len(), 64);
        std::fs::write(&a, b"archive two").unwrap();
        assert_ne!(source_hash(&a).unwrap(), key);
    }
}
