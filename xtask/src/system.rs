//! What the machine must provide: Debian packages by apt, and lavapipe (software Vulkan).

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::{Context, Result, bail};

use crate::{Workspace, run_command, runs, target_dir};

/// Whether this process runs as root (effective uid 0, from `/proc/self/status`).
fn is_root() -> bool {
    fs::read_to_string("/proc/self/status").is_ok_and(|status| {
        status
            .lines()
            .find_map(|line| line.strip_prefix("Uid:"))
            .and_then(|ids| ids.split_whitespace().nth(1))
            == Some("0")
    })
}

/// The Debian packages of lavapipe (software Vulkan) and the Vulkan loader wgpu opens.
const LAVAPIPE_PACKAGES: &[&str] = &["mesa-vulkan-drivers", "libvulkan1"];

/// The packages of `packages` that dpkg does not list as installed; none where there is no dpkg
/// (not Debian or Ubuntu: there [`lavapipe_icd`] says what is missing).
fn missing_debian_packages<'a>(packages: &[&'a str]) -> Vec<&'a str> {
    packages
        .iter()
        .copied()
        .filter(|package| {
            Command::new("dpkg-query")
                .args(["--show", "--showformat=${Status}", package])
                .stderr(Stdio::null())
                .output()
                .is_ok_and(|out| String::from_utf8_lossy(&out.stdout) != "install ok installed")
        })
        .collect()
}

/// `apt-get update` and `apt-get install` of `packages` when running as root with apt-get;
/// otherwise an error saying what to install.
pub(crate) fn apt_install(packages: &[&str], what: &str) -> Result<()> {
    let install = ["install", "-y", "--no-install-recommends"];
    if !is_root() || !runs(Command::new("apt-get").arg("--version")) {
        bail!(
            "{what} is not installed; install it as root with `apt-get update && apt-get {} {}`",
            install.join(" "),
            packages.join(" ")
        );
    }
    eprintln!("xtask: installing {what}: {}", packages.join(" "));
    let apt_get = |args: &[&str]| {
        run_command(
            Command::new("apt-get")
                .args(args)
                .env("DEBIAN_FRONTEND", "noninteractive"),
        )
    };
    apt_get(&["update"])?;
    apt_get(&[&install[..], packages].concat())
}

/// Lavapipe, found (or installed) by [`ensure_lavapipe`]: what a command needs to run its GPU
/// work there.
pub(crate) struct Lavapipe {
    /// The ICD file the Vulkan loader is pointed at.
    pub(crate) icd: PathBuf,
    /// The private `XDG_RUNTIME_DIR` ([`runtime_dir`]), where the caller has none.
    runtime: Option<PathBuf>,
}

impl Lavapipe {
    /// Sets the environment that runs a command's GPU work on lavapipe and makes a missing
    /// adapter a failure (`SPECTEX_REQUIRE_GPU=1`) instead of a skip, with the private runtime
    /// directory that keeps Mesa's loader quiet.
    pub(crate) fn apply(&self, command: &mut Command) {
        command
            .env("VK_DRIVER_FILES", &self.icd)
            .env("VK_ICD_FILENAMES", &self.icd)
            .env("WGPU_ADAPTER_NAME", "llvmpipe")
            .env("SPECTEX_REQUIRE_GPU", "1");
        if let Some(runtime) = &self.runtime {
            command.env("XDG_RUNTIME_DIR", runtime);
        }
    }
}

/// [`Lavapipe`], after installing lavapipe and the Vulkan loader (as root, on Debian or Ubuntu)
/// when they are missing. An ICD named by `VK_DRIVER_FILES`/`VK_ICD_FILENAMES` is the user's
/// choice and installs nothing.
pub(crate) fn ensure_lavapipe(ws: &Workspace) -> Result<Lavapipe> {
    Ok(Lavapipe {
        icd: install_lavapipe()?,
        runtime: runtime_dir(ws)?,
    })
}

/// The lavapipe ICD file, installing lavapipe first where it is missing and can be.
fn install_lavapipe() -> Result<PathBuf> {
    if ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"]
        .iter()
        .all(|var| env::var_os(var).is_none())
    {
        let missing = missing_debian_packages(LAVAPIPE_PACKAGES);
        if !missing.is_empty() {
            apt_install(&missing, "lavapipe (software Vulkan, for the GPU tests)")?;
        }
    }
    lavapipe_icd()
}

/// Where Debian's `mesa-vulkan-drivers` puts the lavapipe ICD file.
const LAVAPIPE_ICD_DIR: &str = "/usr/share/vulkan/icd.d";

/// The lavapipe ICD: `VK_DRIVER_FILES` or `VK_ICD_FILENAMES` when set (first existing file of
/// the list), else `lvp_icd.<arch>.json` from `mesa-vulkan-drivers`.
pub(crate) fn lavapipe_icd() -> Result<PathBuf> {
    for var in ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"] {
        if let Some(value) = env::var_os(var) {
            let found = env::split_paths(&value).find(|p| p.is_file());
            match found {
                Some(path) => return Ok(path),
                None => bail!(
                    "{var} is set to {value:?} but names no existing ICD file; unset it to use \
                     lavapipe from mesa-vulkan-drivers"
                ),
            }
        }
    }
    let preferred = Path::new(LAVAPIPE_ICD_DIR).join(format!("lvp_icd.{}.json", env::consts::ARCH));
    if preferred.is_file() {
        return Ok(preferred);
    }
    let any = fs::read_dir(LAVAPIPE_ICD_DIR).ok().and_then(|dir| {
        dir.filter_map(|e| e.ok().map(|e| e.path())).find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("lvp_icd."))
        })
    });
    any.with_context(|| {
        format!(
            "lavapipe (software Vulkan) is not installed: no {} ; install it with \
             `apt-get install mesa-vulkan-drivers libvulkan1` (Debian/Ubuntu), or point \
             VK_DRIVER_FILES at a Vulkan ICD file",
            preferred.display()
        )
    })
}

/// Mesa's Vulkan loader prints "error: XDG_RUNTIME_DIR is invalid or not set" once per
/// adapter query when the variable is unset (as in CI and containers); the GPU works either
/// way. A private runtime directory under the target dir keeps the output to real errors.
pub(crate) fn private_runtime_dir(ws: &Workspace, command: &mut Command) -> Result<()> {
    if let Some(runtime) = runtime_dir(ws)? {
        command.env("XDG_RUNTIME_DIR", runtime);
    }
    Ok(())
}

/// The private runtime directory of [`private_runtime_dir`], created; `None` where
/// `XDG_RUNTIME_DIR` is set (or the platform has none).
fn runtime_dir(ws: &Workspace) -> Result<Option<PathBuf>> {
    #[cfg(unix)]
    if env::var_os("XDG_RUNTIME_DIR").is_none() {
        use std::os::unix::fs::PermissionsExt;
        let runtime = target_dir(ws).join("xtask-runtime");
        fs::create_dir_all(&runtime)
            .and_then(|()| fs::set_permissions(&runtime, fs::Permissions::from_mode(0o700)))
            .with_context(|| format!("creating {}", runtime.display()))?;
        return Ok(Some(runtime));
    }
    Ok(None)
}
