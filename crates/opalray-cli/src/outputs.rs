//! A command's output files as one transaction: every path is checked and a temporary file
//! created beside it before any work, each output is written to its temporary file, and
//! only when all are written are they renamed over their targets. A failed or interrupted
//! run leaves every earlier file as it was. The temporary files are nameless where the
//! system allows ([`crate::anonymous`]: a killed run leaves no name behind); elsewhere they
//! are named `.opalray-HASH.PID.tmp`, and a killed run's are removed by the next run that
//! writes the same target.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};

use crate::anonymous::Anonymous;

/// One staged output.
struct Staged {
    /// The flag that named it, e.g. `--output`.
    flag: &'static str,
    /// The file the user asked for.
    target: PathBuf,
    /// The temporary file it is written to first: `/proc/self/fd/N` of `anonymous`, or a
    /// named file beside the target.
    temp: PathBuf,
    /// The nameless file, where there is one.
    anonymous: Option<Anonymous>,
}

/// The outputs of one command; dropping it without [`Outputs::commit`] removes the
/// temporary files and leaves the targets untouched.
#[derive(Default)]
pub struct Outputs {
    staged: Vec<Staged>,
}

/// A handle to one staged output.
#[derive(Clone, Copy, Debug)]
pub struct Output(usize);

impl Outputs {
    /// No outputs yet.
    pub fn new() -> Self {
        Outputs::default()
    }

    /// Check `path` for `flag` (its extension one of `allowed`, a file name, its directory
    /// present and writable, not a system folder, distinct from the outputs before it) and
    /// create its temporary file.
    pub fn add(&mut self, flag: &'static str, path: &Path, allowed: &[&str]) -> Result<Output> {
        super::cmd::common::check_extension(flag, path, allowed)?;
        check_target(flag, path)?;
        if let Some(first) = self
            .staged
            .iter()
            .find(|s| same_file(&s.target, path))
            .map(|s| s.flag)
        {
            bail!(
                "{flag} {}: the same file as {first}; give each output its own name",
                path.display()
            );
        }
        opalray::output::remove_stale_temps(path);
        let dir = opalray::output::parent_dir(path);
        let (temp, anonymous) = match Anonymous::create(&dir) {
            Ok(file) => (file.path().to_path_buf(), Some(file)),
            Err(_) => {
                let temp = opalray::output::temp_path(path);
                if let Err(err) = std::fs::OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(&temp)
                {
                    bail!(
                        "{flag} {}: cannot write in directory {}: {}; choose another path",
                        path.display(),
                        dir.display(),
                        plain_io(&err)
                    );
                }
                (temp, None)
            }
        };
        self.staged.push(Staged {
            flag,
            target: path.to_path_buf(),
            temp,
            anonymous,
        });
        Ok(Output(self.staged.len() - 1))
    }

    /// Refuse `dir`, a folder the command writes into (named by `flag`), if it is one of the
    /// outputs or holds one: its files would replace them, or they it.
    pub fn check_folder(&self, flag: &str, dir: &Path) -> Result<()> {
        let folder = dir.canonicalize().ok();
        for staged in &self.staged {
            let parent = opalray::output::parent_dir(&staged.target)
                .canonicalize()
                .ok();
            let inside = folder.is_some() && parent == folder;
            if same_file(&staged.target, dir) || inside {
                bail!(
                    "{flag} {}: the same path as {} {} or a folder holding it; give the folder \
                     its own name",
                    dir.display(),
                    staged.flag,
                    staged.target.display()
                );
            }
        }
        Ok(())
    }

    /// Write `output` with `write`, given the temporary path; an error names the flag and the
    /// target, not the temporary file.
    pub fn write<T, E: std::fmt::Display>(
        &self,
        output: Output,
        write: impl FnOnce(&Path) -> std::result::Result<T, E>,
    ) -> Result<T> {
        let staged = &self.staged[output.0];
        write(&staged.temp).map_err(|err| {
            let text = err.to_string().replace(
                &staged.temp.display().to_string(),
                &staged.target.display().to_string(),
            );
            let text = text
                .strip_prefix(&format!("{}: ", staged.target.display()))
                .unwrap_or(&text)
                .to_string();
            anyhow::anyhow!("{} {}: {text}", staged.flag, staged.target.display())
        })
    }

    /// Rename every temporary file over its target.
    pub fn commit(mut self) -> Result<()> {
        for staged in std::mem::take(&mut self.staged) {
            if let Err(err) = place(&staged) {
                bail!(
                    "{} {}: {}",
                    staged.flag,
                    staged.target.display(),
                    plain_io(&err)
                );
            }
        }
        Ok(())
    }
}

impl Drop for Outputs {
    fn drop(&mut self) {
        // A nameless file goes with its handle; a named one is removed.
        for staged in self.staged.iter().filter(|s| s.anonymous.is_none()) {
            let _ = std::fs::remove_file(&staged.temp);
        }
    }
}

/// Put a written output in place of its target: a nameless file is linked under a temporary
/// name beside the target, then renamed over it (the name lives for the two calls alone); a
/// named one is renamed. On failure no temporary name is left.
fn place(staged: &Staged) -> std::io::Result<()> {
    let named = match &staged.anonymous {
        Some(file) => {
            let named = opalray::output::temp_path(&staged.target);
            let _ = std::fs::remove_file(&named);
            file.link(&named)?;
            named
        }
        None => staged.temp.clone(),
    };
    std::fs::rename(&named, &staged.target).inspect_err(|_| {
        let _ = std::fs::remove_file(&named);
    })
}

/// An I/O error's text without Rust's ` (os error N)`.
pub fn plain_io(err: &std::io::Error) -> String {
    let text = err.to_string();
    match text.find(" (os error") {
        Some(at) => text[..at].to_string(),
        None => text,
    }
}

/// Refuse a target that is not a plain file path in an existing, ordinary directory.
fn check_target(flag: &str, path: &Path) -> Result<()> {
    let shown = path.display();
    if path.as_os_str().as_encoded_bytes().ends_with(b"/") || path.file_name().is_none() {
        bail!("{flag} {shown}: names a directory, not a file; give a file name such as out.png");
    }
    if path.is_dir() {
        bail!("{flag} {shown}: is a directory; give a file name inside it");
    }
    if path.exists() && !path.is_file() {
        bail!("{flag} {shown}: is not a regular file (a device or pipe); give a file name");
    }
    let dir = opalray::output::parent_dir(path);
    if !dir.exists() {
        bail!(
            "{flag} {shown}: directory {} does not exist; create it first or choose another path",
            dir.display()
        );
    }
    if !dir.is_dir() {
        bail!(
            "{flag} {shown}: {} is a file, not a directory; choose another path",
            dir.display()
        );
    }
    if let Ok(real) = dir.canonicalize() {
        if ["/proc", "/sys", "/dev"]
            .iter()
            .any(|system| real.starts_with(system))
        {
            bail!(
                "{flag} {shown}: {} is a system folder, not for files; choose another path",
                real.display()
            );
        }
    }
    Ok(())
}

/// Whether two paths name the same file whatever the spelling (the directory resolved).
fn same_file(a: &Path, b: &Path) -> bool {
    let key = |path: &Path| {
        (
            opalray::output::parent_dir(path).canonicalize().ok(),
            path.file_name().map(|n| n.to_owned()),
        )
    };
    key(a) == key(b)
}
