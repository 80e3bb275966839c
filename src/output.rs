//! Files written whole or not at all: the bytes go to a temporary file beside the output, which
//! takes the output's name only once everything is written. An error (or a panic) removes the
//! temporary file; nothing is ever left half-written under the output's name. A program that
//! calls [`remove_partials_on_interrupt`] (the CLI does; a library must not take Ctrl-C from its
//! host, Python for one) also removes them on Ctrl-C.

use crate::error::Error;
use crate::parallel::PerProcess;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

/// The temporary files being written, for the Ctrl-C handler. Each process has its own: a child
/// forked while its parent's thread was writing (Python's `save` releases the GIL) would wait
/// for good for the lock that thread held, and the parent's files are not the child's.
static PARTIAL: PerProcess<Mutex<Vec<PathBuf>>> = PerProcess::new(|| Mutex::new(Vec::new()));

fn partial() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    PARTIAL.get().lock().unwrap_or_else(PoisonError::into_inner)
}

/// On Ctrl-C (SIGINT, SIGTERM, SIGHUP), every temporary file still being written is removed and
/// the process exits with status 130, as a shell reports an interrupted command.
pub fn remove_partials_on_interrupt() {
    // The handler runs on a thread of its own (ctrlc's), so it may lock and remove files.
    let _ = ctrlc::set_handler(|| {
        let left: Vec<PathBuf> = partial().drain(..).collect();
        for path in &left {
            let _ = std::fs::remove_file(path);
        }
        eprintln!("bvhview: interrupted; no output was left half-written");
        // `_exit`, not `process::exit`: the exit handlers of the GL libraries must not run while
        // the main thread may still be drawing with them (that crashed with SIGSEGV).
        // SAFETY: ends the process at once; nothing after it runs.
        unsafe { libc::_exit(130) }
    });
}

/// An output file being written; [`AtomicFile::commit`] gives it its name.
pub struct AtomicFile {
    temporary: PathBuf,
    path: PathBuf,
    writer: Option<BufWriter<std::fs::File>>,
}

impl AtomicFile {
    /// Starts writing `path` (its folder must exist).
    pub fn create(path: &Path) -> Result<AtomicFile, Error> {
        let name = path
            .file_name()
            .map_or("out".into(), |n| n.to_string_lossy());
        let temporary = path.with_file_name(format!(".{name}.{}.partial", std::process::id()));
        let file = std::fs::File::create(&temporary).map_err(|e| Error::output(path, e))?;
        partial().push(temporary.clone());
        Ok(AtomicFile {
            temporary,
            path: path.to_path_buf(),
            writer: Some(BufWriter::new(file)),
        })
    }

    /// Flushes and renames the file to its name.
    pub fn commit(mut self) -> Result<(), Error> {
        let writer = self.writer.take().expect("committed once");
        let file = writer
            .into_inner()
            .map_err(|e| Error::output(&self.path, e.into_error()))?;
        file.sync_all().map_err(|e| Error::output(&self.path, e))?;
        drop(file);
        let renamed =
            std::fs::rename(&self.temporary, &self.path).map_err(|e| Error::output(&self.path, e));
        if renamed.is_err() {
            let _ = std::fs::remove_file(&self.temporary);
        }
        partial().retain(|p| *p != self.temporary);
        renamed
    }
}

impl Write for AtomicFile {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.writer.as_mut().expect("not committed").write(bytes)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.writer.as_mut().expect("not committed").flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = std::fs::remove_file(&self.temporary);
            partial().retain(|p| *p != self.temporary);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_appears_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("bvhview-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("out.csv");
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"half").unwrap();
        assert!(!path.exists(), "nothing under the name while writing");
        drop(file);
        assert!(!path.exists());
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            0,
            "no temporary left"
        );
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"whole").unwrap();
        file.commit().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"whole");
        std::fs::remove_dir_all(dir).unwrap();
    }
}
