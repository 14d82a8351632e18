//! Anonymous files: written without a name (Linux `O_TMPFILE`) and linked into their folder
//! only when complete, so that a process killed while writing (`kill -9`) leaves no name
//! behind. Elsewhere (another system, a file system without `O_TMPFILE`, no `/proc`) the
//! caller falls back to a named temporary file.
//!
//! The file is written through `/proc/self/fd/N`, a path every writer can open (opening it
//! again reaches the same nameless file), and linked with `linkat(…, AT_SYMLINK_FOLLOW)`
//! through the same path (rustix's safe wrappers: no `unsafe` here).

use std::fs::File;
use std::path::{Path, PathBuf};

/// A nameless file in a folder, held open.
pub struct Anonymous {
    file: File,
    /// `/proc/self/fd/N`: where writers open it.
    path: PathBuf,
}

impl Anonymous {
    /// A nameless file in `dir`, or why there cannot be one (the caller then falls back to
    /// a named temporary file).
    #[cfg(target_os = "linux")]
    pub fn create(dir: &Path) -> std::io::Result<Self> {
        use rustix::fs::{openat, Mode, OFlags, CWD};
        use std::os::fd::AsRawFd;
        let fd = openat(
            CWD,
            dir,
            OFlags::TMPFILE | OFlags::RDWR | OFlags::CLOEXEC,
            Mode::from_raw_mode(0o666),
        )?;
        let file = File::from(fd);
        let path = PathBuf::from(format!("/proc/self/fd/{}", file.as_raw_fd()));
        // Without /proc the file could not be reached by path, nor linked.
        if !path.exists() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::Unsupported,
                "no /proc/self/fd",
            ));
        }
        Ok(Anonymous { file, path })
    }

    /// Nameless files are Linux's alone.
    #[cfg(not(target_os = "linux"))]
    pub fn create(_dir: &Path) -> std::io::Result<Self> {
        Err(std::io::Error::new(
            std::io::ErrorKind::Unsupported,
            "no anonymous files here",
        ))
    }

    /// The path writers open it by (`/proc/self/fd/N`).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flush it to disk and give it the name `name` (which must not exist yet).
    #[cfg(target_os = "linux")]
    pub fn link(&self, name: &Path) -> std::io::Result<()> {
        use rustix::fs::{linkat, AtFlags, CWD};
        self.file.sync_all()?;
        linkat(CWD, &self.path, CWD, name, AtFlags::SYMLINK_FOLLOW)?;
        Ok(())
    }

    /// Never reached: [`Anonymous::create`] fails here.
    #[cfg(not(target_os = "linux"))]
    pub fn link(&self, _name: &Path) -> std::io::Result<()> {
        Err(std::io::Error::new(
            std::io::ErrorKind::Unsupported,
            "no anonymous files here",
        ))
    }
}

/// Write the file `path` through `write` (given the path to write to) so that no name but
/// `path` itself ever appears for longer than a link and a rename: a nameless file in its
/// folder, linked under a temporary name when complete and renamed over `path`. Where there
/// are no nameless files, `write` is given `path` itself (and writes it atomically through a
/// named temporary file, [`opalray::output::write_atomic`]).
pub fn write_file<E: std::fmt::Display>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
) -> anyhow::Result<()> {
    let Ok(file) = Anonymous::create(&opalray::output::parent_dir(path)) else {
        return write(path).map_err(|e| anyhow::anyhow!("{e}"));
    };
    write(file.path()).map_err(|e| {
        let text = e.to_string();
        anyhow::anyhow!(
            "{}",
            text.replace(
                &file.path().display().to_string(),
                &path.display().to_string()
            )
        )
    })?;
    let named = opalray::output::temp_path(path);
    let _ = std::fs::remove_file(&named);
    let placed = file
        .link(&named)
        .and_then(|()| std::fs::rename(&named, path));
    placed.map_err(|e| {
        let _ = std::fs::remove_file(&named);
        anyhow::anyhow!("{}: {}", path.display(), crate::outputs::plain_io(&e))
    })
}
