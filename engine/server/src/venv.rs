//! The project's own Python virtualenv holding the pinned rcssservermj.

use crate::ServerError;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The server version every test and match runs against.
pub const RCSSSMJ_VERSION: &str = "0.2.1";

/// The Ray version `--ray` runs on (driver and cluster must agree; the driver checks).
pub const RAY_VERSION: &str = "2.60.0";

/// A virtualenv with the server installed.
#[derive(Debug, Clone)]
pub struct Installation {
    pub venv: PathBuf,
}

impl Installation {
    /// The `rcssservermj` entry point.
    pub fn server_program(&self) -> PathBuf {
        self.venv.join("bin").join("rcssservermj")
    }

    /// The virtualenv's Python (it has `mujoco` too, for the kinematics fixtures).
    pub fn python(&self) -> PathBuf {
        self.venv.join("bin").join("python")
    }
}

/// The repository root: `LIBERO_HOME` if set, else where this crate was built from.
pub fn project_root() -> PathBuf {
    std::env::var_os("LIBERO_HOME")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
}

/// Where the virtualenv lives: `LIBERO_VENV`, else `.venv/` in the repository.
pub fn venv_path() -> PathBuf {
    std::env::var_os("LIBERO_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| project_root().join(".venv"))
}

/// Make sure the pinned server is installed, installing it on first use. Safe to call from many
/// processes at once: they take turns on a lock file, and all but the first find it done.
pub fn ensure_installed() -> Result<Installation, ServerError> {
    let venv = venv_path();
    let install = Installation { venv: venv.clone() };
    let marker = venv.join(format!(".libero-rcsssmj-{RCSSSMJ_VERSION}"));
    if marker.exists() && install.server_program().exists() {
        return Ok(install);
    }
    let parent = venv.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent)
        .map_err(|e| ServerError::Io(parent.display().to_string(), e))?;
    let lock_path = parent.join(".libero-venv.lock");
    let lock = File::create(&lock_path)
        .map_err(|e| ServerError::Io(lock_path.display().to_string(), e))?;
    lock.lock()
        .map_err(|e| ServerError::Io(lock_path.display().to_string(), e))?;
    if marker.exists() && install.server_program().exists() {
        return Ok(install);
    }
    log::info!(
        "installing rcsssmj=={RCSSSMJ_VERSION} into {} (first use only)",
        venv.display()
    );
    if !install.python().exists() {
        let python = which_python()?;
        run(Command::new(&python).arg("-m").arg("venv").arg(&venv)).map_err(|detail| {
            ServerError::Venv {
                path: venv.display().to_string(),
                detail,
            }
        })?;
    }
    pip_install(&install, &format!("rcsssmj=={RCSSSMJ_VERSION}"))?;
    File::create(&marker).map_err(|e| ServerError::Io(marker.display().to_string(), e))?;
    Ok(install)
}

/// Make sure the pinned Ray is in the virtualenv too (for `--ray` and `ray start`), installing
/// it on first use; the server comes first.
pub fn ensure_ray_installed() -> Result<Installation, ServerError> {
    let install = ensure_installed()?;
    let marker = install.venv.join(format!(".libero-ray-{RAY_VERSION}"));
    if marker.exists() {
        return Ok(install);
    }
    let lock_path = install.venv.join(".libero-ray.lock");
    let lock = File::create(&lock_path)
        .map_err(|e| ServerError::Io(lock_path.display().to_string(), e))?;
    lock.lock()
        .map_err(|e| ServerError::Io(lock_path.display().to_string(), e))?;
    if marker.exists() {
        return Ok(install);
    }
    log::info!(
        "installing ray=={RAY_VERSION} into {} (first use only)",
        install.venv.display()
    );
    pip_install(&install, &format!("ray=={RAY_VERSION}"))?;
    File::create(&marker).map_err(|e| ServerError::Io(marker.display().to_string(), e))?;
    Ok(install)
}

/// `pip install SPEC` into the virtualenv.
fn pip_install(install: &Installation, spec: &str) -> Result<(), ServerError> {
    run(Command::new(install.python())
        .args([
            "-m",
            "pip",
            "install",
            "--disable-pip-version-check",
            "--quiet",
        ])
        .arg(spec))
    .map_err(|detail| ServerError::Pip {
        version: spec.to_string(),
        path: install.venv.display().to_string(),
        detail,
    })
}

fn which_python() -> Result<PathBuf, ServerError> {
    for candidate in ["python3", "python"] {
        let ok = Command::new(candidate)
            .arg("--version")
            .output()
            .map(|o| o.status.success())
            .unwrap_or(false);
        if ok {
            return Ok(PathBuf::from(candidate));
        }
    }
    Err(ServerError::NoPython)
}

/// Run a command to completion; on failure, its stderr tail.
fn run(cmd: &mut Command) -> Result<(), String> {
    let out = cmd.output().map_err(|e| e.to_string())?;
    if out.status.success() {
        return Ok(());
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    let tail: Vec<&str> = stderr.lines().rev().take(8).collect();
    Err(format!(
        "{} — {}",
        out.status,
        tail.into_iter().rev().collect::<Vec<_>>().join("\n")
    ))
}
