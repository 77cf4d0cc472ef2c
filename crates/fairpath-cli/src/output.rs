//! Writing files so that a failure never leaves a partial output behind,
//! with the permissions a controller or file share expects, and never over
//! the program being read unless asked to.

use anyhow::{bail, Context, Result};
use fairpath_gcode::text_out::TextOut;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Permissions asked for a new file: read and write for all, less the
/// process's umask (what `open(2)` with `O_CREAT` and `creat` give, and what
/// every editor and `cp` leave).
#[cfg(unix)]
pub const NEW_FILE_MODE: u32 = 0o666;

/// Writes `bytes` to a temporary file beside `path`, then renames it over
/// `path`: readers see the old file or the whole new one, never a part.
///
/// The file written gets the permission bits of the file it replaces, or
/// [`NEW_FILE_MODE`] less the umask for a new one (the temporary file is
/// created with them, so the kernel applies the umask), not the 0600 of a
/// temporary file: a controller or file share running as another user
/// must be able to read it. Where `path` is a symbolic link the file it
/// points to is replaced and the link kept. Owner, group and extended
/// attributes are those of a new file; a hard-linked file's other names
/// keep the old contents (the rename makes a new file).
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes)
        .with_context(|| format!("cannot write {}", path.display()))?;
    file.commit()
}

/// A file written beside `path` that becomes `path` only when committed
/// ([`AtomicFile::commit`], as [`write_atomically`] writes it): dropped
/// uncommitted, it leaves nothing behind. Writes are buffered.
pub struct AtomicFile {
    tmp: tempfile::NamedTempFile,
    buf: std::io::BufWriter<std::fs::File>,
    target: PathBuf,
    path: PathBuf,
    existing: Option<std::fs::Permissions>,
}

impl AtomicFile {
    /// A new temporary file beside `path` (beside the file it links to).
    pub fn create(path: &Path) -> Result<AtomicFile> {
        let target = resolve_link(path)?;
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let existing = std::fs::metadata(&target).ok().map(|m| m.permissions());
        let mut builder = tempfile::Builder::new();
        builder.prefix(".fairpath-");
        #[cfg(unix)]
        if existing.is_none() {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(NEW_FILE_MODE));
        }
        let tmp = builder
            .tempfile_in(&dir)
            .with_context(|| format!("cannot create a temporary file in {}", dir.display()))?;
        let file = tmp
            .as_file()
            .try_clone()
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(AtomicFile {
            tmp,
            buf: std::io::BufWriter::new(file),
            target,
            path: path.to_path_buf(),
            existing,
        })
    }

    /// Renames the file written over `path`, with the permissions of the
    /// file it replaces (see [`write_atomically`]).
    pub fn commit(mut self) -> Result<()> {
        let path = self.path.clone();
        self.buf
            .flush()
            .with_context(|| format!("cannot write {}", path.display()))?;
        if let Some(perms) = self.existing.take() {
            self.tmp
                .as_file()
                .set_permissions(perms)
                .with_context(|| format!("cannot set the permissions of {}", path.display()))?;
        }
        let AtomicFile {
            tmp, buf, target, ..
        } = self;
        drop(buf);
        tmp.persist(&target)
            .map_err(|e| e.error)
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.buf.write(b)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.buf.flush()
    }
}

/// Where a program being written goes: a file, written atomically
/// ([`AtomicFile`]), or standard output (`-`), which gets the text only
/// when it is committed (held in an anonymous temporary file until then:
/// a job that fails part-way writes nothing).
pub enum OutputSink {
    File(AtomicFile),
    Stdout(std::io::BufWriter<std::fs::File>),
}

impl OutputSink {
    /// The sink for `path` (`-`: standard output).
    pub fn create(path: &Path) -> Result<OutputSink> {
        if crate::read::is_stdio(path) {
            let f = tempfile::tempfile().context("cannot create a temporary file")?;
            Ok(OutputSink::Stdout(std::io::BufWriter::new(f)))
        } else {
            AtomicFile::create(path).map(OutputSink::File)
        }
    }

    /// The text written becomes the output.
    pub fn commit(self) -> Result<()> {
        match self {
            OutputSink::File(f) => f.commit(),
            OutputSink::Stdout(buf) => {
                use std::io::Seek;
                let mut f = buf.into_inner().map_err(|e| e.into_error())?;
                f.rewind()?;
                let mut out = std::io::stdout().lock();
                std::io::copy(&mut f, &mut out)
                    .and_then(|_| out.flush())
                    .context("cannot write standard output")?;
                Ok(())
            }
        }
    }
}

impl Write for OutputSink {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        match self {
            OutputSink::File(f) => f.write(b),
            OutputSink::Stdout(w) => w.write(b),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            OutputSink::File(f) => f.flush(),
            OutputSink::Stdout(w) => w.flush(),
        }
    }
}

impl OutputSink {
    /// The temporary file the text goes to, with what was buffered written
    /// to it.
    fn file(&mut self) -> std::io::Result<&mut std::fs::File> {
        let buf = match self {
            OutputSink::File(f) => &mut f.buf,
            OutputSink::Stdout(w) => w,
        };
        buf.flush()?;
        Ok(buf.get_mut())
    }
}

/// The job writes its text to the temporary file as it goes, reads it back
/// from there and cuts it back there (`fairpath_gcode::text_out`).
impl TextOut for OutputSink {
    fn append(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.file()?.append(bytes)
    }
    fn written(&mut self) -> std::io::Result<u64> {
        self.file()?.written()
    }
    fn cut(&mut self, len: u64) -> std::io::Result<()> {
        self.file()?.cut(len)
    }
    fn read_from(&mut self, from: u64) -> std::io::Result<Box<dyn std::io::Read + '_>> {
        self.file()?.read_from(from)
    }
}

/// Writes `bytes` to `path` atomically ([`write_atomically`]), or to
/// standard output when `path` is `-`.
pub fn write_output(path: &Path, bytes: &[u8]) -> Result<()> {
    if crate::read::is_stdio(path) {
        let mut out = std::io::stdout().lock();
        out.write_all(bytes)
            .and_then(|_| out.flush())
            .context("cannot write standard output")
    } else {
        write_atomically(path, bytes)
    }
}

/// `path`, or the file it names through symbolic links when it is one
/// (a dangling link names the file it would create).
fn resolve_link(path: &Path) -> Result<PathBuf> {
    let mut p = path.to_path_buf();
    // A bounded walk: a loop of links is an error, as open(2) says ELOOP.
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p)
                    .with_context(|| format!("cannot read the link {}", p.display()))?;
                p = match p.parent() {
                    Some(d) if to.is_relative() => d.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    bail!("{}: too many levels of symbolic links", path.display())
}

/// Symbolic links followed before giving up (Linux's `MAXSYMLINKS`, 40).
const MAX_LINKS: usize = 40;

/// Whether `a` and `b` name the same existing file: the same device and
/// inode on unix (also through hard links, symbolic links and different
/// spellings of the path), the same canonical path elsewhere. A file that
/// does not exist is the same as no other, nor is `-` (standard input or
/// output).
pub fn same_file(a: &Path, b: &Path) -> bool {
    if crate::read::is_stdio(a) || crate::read::is_stdio(b) {
        return false;
    }
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
    }
}

/// Refuses to write `output` over `input` (the same file, however named):
/// `what` says which option names it. The error says how to replace the
/// input when `in_place_flag` is given (`--in-place`). A usage error
/// (exit status 2).
pub fn refuse_overwrite(
    input: &Path,
    output: &Path,
    what: &str,
    in_place_flag: Option<&str>,
) -> Result<()> {
    if same_file(input, output) {
        return Err(crate::usage::usage(match in_place_flag {
            Some(flag) => format!(
                "{what} {} is the input program {} (the same file): refusing to overwrite it; \
                 pass {flag} to replace the input, or name another output",
                output.display(),
                input.display()
            ),
            None => format!(
                "{what} {} is the input program {} (the same file): refusing to overwrite it; \
                 name another file",
                output.display(),
                input.display()
            ),
        }));
    }
    Ok(())
}

/// The file `smooth` writes: `-o` (`-`: standard output; never the input,
/// however named, unless `--in-place`), the input with `--in-place` (then
/// `-o`, if given, must name it), else [`default_output`] beside the input,
/// or standard output when the input is standard input. Conflicts are
/// usage errors.
pub fn smooth_output(
    input: &Path,
    output: Option<PathBuf>,
    in_place: bool,
    json: bool,
) -> Result<PathBuf> {
    use crate::read::is_stdio;
    use crate::usage::usage;
    if in_place && is_stdio(input) {
        return Err(usage(
            "--in-place replaces the input file, but the input is standard input (-): \
             leave --in-place out",
        ));
    }
    match (output, in_place) {
        (Some(o), false) => {
            refuse_overwrite(input, &o, "-o", Some("--in-place"))?;
            Ok(o)
        }
        (Some(o), true) if !same_file(input, &o) => Err(usage(format!(
            "--in-place replaces the input {}, but -o names another file {}: give one of them",
            input.display(),
            o.display()
        ))),
        (_, true) => Ok(input.to_path_buf()),
        (None, false) if is_stdio(input) => Ok(PathBuf::from("-")),
        (None, false) => Ok(default_output(input, json)),
    }
}

/// The output's name when `-o` is left out: `NAME.smoothed.EXT` beside
/// `NAME.EXT` (the input's extension kept; `NAME.smoothed.json` for the
/// JSON format; `NAME.smoothed` for an input without an extension).
pub fn default_output(input: &Path, json: bool) -> PathBuf {
    let stem = input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "program".to_string());
    let ext = if json {
        Some("json".to_string())
    } else {
        input.extension().map(|e| e.to_string_lossy().into_owned())
    };
    let name = match ext {
        Some(e) => format!("{stem}.smoothed.{e}"),
        None => format!("{stem}.smoothed"),
    };
    input.with_file_name(name)
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    fn mode(p: &Path) -> u32 {
        std::fs::metadata(p).unwrap().permissions().mode() & 0o7777
    }

    /// The umask, read without changing it: the mode `create` gives a
    /// probe file asking for 0666.
    fn umask_of(dir: &Path) -> u32 {
        let probe = dir.join("probe");
        std::fs::File::create(&probe).unwrap();
        let m = mode(&probe);
        std::fs::remove_file(&probe).unwrap();
        0o666 & !m
    }

    #[test]
    fn a_new_file_gets_0666_less_the_umask() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("new.ngc");
        write_atomically(&out, b"G0 X0\n").unwrap();
        assert_eq!(mode(&out), 0o666 & !umask_of(dir.path()));
        assert_eq!(std::fs::read(&out).unwrap(), b"G0 X0\n");
    }

    #[test]
    fn a_replaced_file_keeps_its_permissions() {
        let dir = tempfile::tempdir().unwrap();
        for m in [0o644, 0o640, 0o604, 0o755] {
            let out = dir.path().join("old.ngc");
            std::fs::write(&out, b"old").unwrap();
            std::fs::set_permissions(&out, std::fs::Permissions::from_mode(m)).unwrap();
            write_atomically(&out, b"new").unwrap();
            assert_eq!(mode(&out), m);
            assert_eq!(std::fs::read(&out).unwrap(), b"new");
        }
    }

    #[test]
    fn a_symbolic_link_is_written_through() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.ngc");
        std::fs::write(&real, b"old").unwrap();
        std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o644)).unwrap();
        let link = dir.path().join("link.ngc");
        std::os::unix::fs::symlink("real.ngc", &link).unwrap();
        write_atomically(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        assert_eq!(mode(&real), 0o644);
    }

    #[test]
    fn the_same_file_is_found_through_other_names() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.ngc");
        std::fs::write(&a, b"x").unwrap();
        let sub = dir.path().join("sub");
        std::fs::create_dir(&sub).unwrap();
        let dotted = sub.join("..").join("a.ngc");
        let hard = dir.path().join("hard.ngc");
        std::fs::hard_link(&a, &hard).unwrap();
        let soft = dir.path().join("soft.ngc");
        std::os::unix::fs::symlink(&a, &soft).unwrap();
        for other in [&a, &dotted, &hard, &soft] {
            assert!(same_file(&a, other), "{}", other.display());
        }
        let b = dir.path().join("b.ngc");
        assert!(!same_file(&a, &b));
        std::fs::write(&b, b"x").unwrap();
        assert!(!same_file(&a, &b));
        assert!(refuse_overwrite(&a, &b, "-o", Some("--in-place")).is_ok());
        let e = refuse_overwrite(&a, &hard, "-o", Some("--in-place")).unwrap_err();
        assert!(e.to_string().contains("--in-place"), "{e}");
        assert!(!same_file(Path::new("-"), &a));
    }

    #[test]
    fn default_names_keep_the_extension_beside_the_input() {
        let d = |p: &str, json| default_output(Path::new(p), json);
        assert_eq!(d("dir/part.ngc", false), Path::new("dir/part.smoothed.ngc"));
        assert_eq!(d("part.NC", false), Path::new("part.smoothed.NC"));
        assert_eq!(d("dir/part.ngc", true), Path::new("dir/part.smoothed.json"));
        assert_eq!(d("part", false), Path::new("part.smoothed"));
    }
}
