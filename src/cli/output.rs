//! Output files that appear whole or not at all: write to a temporary file beside the target,
//! rename on success, remove on failure or on a signal ([`super::cleanup`]). A symlinked output
//! is followed (its target is replaced, the link kept); a directory, FIFO, socket or device, or
//! a file that is one of the command's inputs, is refused before any work is done.

use super::cleanup;
use anyhow::{Context, Result, bail};
use raytree::Image;
use std::fs::File;
use std::io::Write;
use std::os::unix::fs::{FileTypeExt, MetadataExt};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The files a command reads (scene, meshes, images), by device and inode, so that no output
/// can overwrite one of them whatever path names it.
#[derive(Default)]
pub struct Inputs(Vec<(u64, u64, PathBuf)>);

impl Inputs {
    /// Identify `paths` (those that cannot be read are skipped: they cannot be overwritten
    /// through another name either).
    pub fn new<'a>(paths: impl IntoIterator<Item = &'a Path>) -> Self {
        Self(
            paths
                .into_iter()
                .filter_map(|p| {
                    let m = std::fs::metadata(p).ok()?;
                    Some((m.dev(), m.ino(), p.to_path_buf()))
                })
                .collect(),
        )
    }

    fn check(&self, target: &Path, m: &std::fs::Metadata) -> Result<()> {
        if let Some((_, _, p)) = self
            .0
            .iter()
            .find(|(d, i, _)| (*d, *i) == (m.dev(), m.ino()))
        {
            bail!(
                "cannot write {}: it is {}, an input of this command; not overwritten",
                target.display(),
                p.display()
            );
        }
        Ok(())
    }
}

/// Where `target` really is: a symlink (chain) is followed; a dangling one is refused.
fn resolve(target: &Path) -> Result<PathBuf> {
    match std::fs::symlink_metadata(target) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(target).with_context(|| {
            format!(
                "cannot write {}: it is a symlink to a missing file",
                target.display()
            )
        }),
        _ => Ok(target.to_path_buf()),
    }
}

/// A short temporary name in `dir` (short so that a target name of 255 bytes still works).
fn temp_in(dir: &Path) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    dir.join(format!(
        ".rt{}-{}.tmp",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ))
}

fn parent_of(p: &Path) -> &Path {
    p.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// A reserved output path; dropping it without [`Pending::commit`] leaves no file behind.
pub struct Pending {
    shown: PathBuf,
    target: PathBuf,
    temp: PathBuf,
    file: Option<File>,
}

impl Pending {
    /// Reserve `target` by creating a temporary file in its (real) directory; refuse a target
    /// that is a directory, a special file or one of `inputs`.
    pub fn create(target: &Path, inputs: &Inputs) -> Result<Self> {
        let real = resolve(target)?;
        if real.file_name().is_none() {
            bail!("cannot write {}: not a file name", target.display());
        }
        if let Ok(m) = std::fs::metadata(&real) {
            let t = m.file_type();
            if t.is_dir() {
                bail!("cannot write {}: it is a directory", target.display());
            }
            if t.is_fifo() || t.is_socket() || t.is_block_device() || t.is_char_device() {
                bail!(
                    "cannot write {}: it is a FIFO, socket or device, not a regular file; not replaced",
                    target.display()
                );
            }
            inputs.check(target, &m)?;
        }
        let temp = temp_in(parent_of(&real));
        cleanup::register(&temp);
        let file = match File::options().write(true).create_new(true).open(&temp) {
            Ok(f) => f,
            Err(e) => {
                cleanup::forget(&temp);
                return Err(e).with_context(|| format!("cannot write {}", target.display()));
            }
        };
        Ok(Self {
            shown: target.to_path_buf(),
            target: real,
            temp,
            file: Some(file),
        })
    }

    /// Write `bytes` and move the file into place.
    pub fn commit(mut self, bytes: &[u8]) -> Result<()> {
        let mut file = self.file.take().context("output already written")?;
        file.write_all(bytes)
            .and_then(|()| file.sync_all())
            .with_context(|| format!("cannot write {}", self.shown.display()))?;
        drop(file);
        let temp = std::mem::take(&mut self.temp);
        let renamed = cleanup::settle(&temp, || std::fs::rename(&temp, &self.target));
        if let Err(e) = renamed {
            let _ = std::fs::remove_file(&temp);
            return Err(e).with_context(|| format!("cannot write {}", self.shown.display()));
        }
        Ok(())
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if !self.temp.as_os_str().is_empty() {
            let _ = std::fs::remove_file(&self.temp);
            cleanup::forget(&self.temp);
        }
    }
}

/// Who named an output: the user, by a flag (replacing an existing file of that name is what
/// was asked), or the command, by deriving it from another name (`out.albedo.png` from `-o
/// out.png`): an existing file there is the user's and is refused unless `--force`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// Named on the command line.
    Named,
    /// Derived by the command; the flag that made it (for the message).
    Derived(&'static str),
}

/// The identity of an output for collision checks: its directory resolved (symlinks, `.` and
/// `..`) joined with its file name, and the device and inode of an existing file.
fn identity(target: &Path) -> Result<(PathBuf, Option<(u64, u64)>)> {
    let name = target
        .file_name()
        .with_context(|| format!("cannot write {}: not a file name", target.display()))?;
    let dir = std::fs::canonicalize(parent_of(target))
        .with_context(|| format!("cannot write {}: its directory", target.display()))?;
    let id = std::fs::metadata(target).ok().map(|m| (m.dev(), m.ino()));
    Ok((dir.join(name), id))
}

struct Slot {
    shown: PathBuf,
    target: PathBuf,
    key: (PathBuf, Option<(u64, u64)>),
    staged: Option<PathBuf>,
}

/// Every output file of one command, written as a set: each is checked when reserved (before
/// any work: special files, inputs, two outputs with one name however spelled, derived names
/// that would replace a user's file), its bytes are staged to a temporary file beside it only
/// when the work is done, and [`OutputSet::commit`] moves all of them into place at once with
/// signal cleanup held off, so a signal leaves either no target changed or every one written.
pub struct OutputSet<'a> {
    inputs: &'a Inputs,
    force: bool,
    slots: Vec<Slot>,
}

impl<'a> OutputSet<'a> {
    /// An empty set; `force` allows derived names to replace existing files.
    pub fn new(inputs: &'a Inputs, force: bool) -> Self {
        Self {
            inputs,
            force,
            slots: Vec::new(),
        }
    }

    /// Check `target` as an output and return its slot. Probes that a temporary file can be
    /// created beside it (and removes it again, so an abort during the work leaves nothing).
    pub fn reserve(&mut self, target: &Path, origin: Origin) -> Result<usize> {
        let real = resolve(target)?;
        drop(Pending::create(target, self.inputs)?);
        let key = identity(&real)?;
        if let Some(other) = self
            .slots
            .iter()
            .find(|s| s.key.0 == key.0 || (key.1.is_some() && s.key.1 == key.1))
        {
            bail!(
                "two outputs of this command would both be {}: {} and {}; give each a file of its own",
                escape(&real),
                escape(&other.shown),
                escape(target)
            );
        }
        if let (Origin::Derived(flag), Some(_), false) = (origin, key.1, self.force) {
            bail!(
                "{} (written for {flag}) exists and this command did not create it; not replaced: move it away or add --force",
                escape(target)
            );
        }
        self.slots.push(Slot {
            shown: target.to_path_buf(),
            target: real,
            key,
            staged: None,
        });
        Ok(self.slots.len() - 1)
    }

    /// Write the bytes of slot `i` to its temporary file (synced); nothing is replaced yet.
    pub fn stage(&mut self, i: usize, bytes: &[u8]) -> Result<()> {
        let slot = &mut self.slots[i];
        let temp = temp_in(parent_of(&slot.target));
        cleanup::register(&temp);
        slot.staged = Some(temp.clone());
        let written = File::options()
            .write(true)
            .create_new(true)
            .open(&temp)
            .and_then(|mut f| f.write_all(bytes).and_then(|()| f.sync_all()));
        written.with_context(|| format!("cannot write {}", slot.shown.display()))
    }

    /// Move every staged file into place. The renames run with the signal cleanup locked out
    /// (a signal waits for them), so the set is all or nothing from the user's view.
    pub fn commit(mut self) -> Result<()> {
        if let Some(s) = self.slots.iter().find(|s| s.staged.is_none()) {
            bail!(
                "internal: {} was reserved but not written",
                s.shown.display()
            );
        }
        let temps: Vec<PathBuf> = self.slots.iter().filter_map(|s| s.staged.clone()).collect();
        // A test hook (tests/hostile/round3.rs): a pause before each rename, so that a signal
        // can be sent while the set is being moved into place.
        let pause = std::env::var("RAYTREE_TEST_COMMIT_PAUSE_MS")
            .ok()
            .and_then(|v| v.parse().ok())
            .map(std::time::Duration::from_millis);
        cleanup::settle_all(&temps, || {
            for s in &mut self.slots {
                if let Some(p) = pause {
                    std::thread::sleep(p);
                }
                let temp = s.staged.take().expect("checked above");
                if let Err(e) = std::fs::rename(&temp, &s.target) {
                    let _ = std::fs::remove_file(&temp);
                    return Err(e).with_context(|| format!("cannot write {}", s.shown.display()));
                }
            }
            Ok(())
        })
    }
}

impl Drop for OutputSet<'_> {
    fn drop(&mut self) {
        for t in self.slots.iter_mut().filter_map(|s| s.staged.take()) {
            let _ = std::fs::remove_file(&t);
            cleanup::forget(&t);
        }
    }
}

fn escape(p: &Path) -> String {
    raytree::input::escape_controls(&p.display().to_string()).into_owned()
}

/// An output directory: an existing directory is used as it is (only the command's own files
/// in it are replaced, each atomically; nothing else is touched or deleted), a missing one is
/// created and removed again if the command fails.
pub struct OutDir {
    path: PathBuf,
    created: Vec<PathBuf>,
}

impl OutDir {
    /// Use or create `path`.
    pub fn create(path: &Path) -> Result<Self> {
        let real = resolve(path)?;
        if let Ok(m) = std::fs::metadata(&real) {
            if !m.is_dir() {
                bail!(
                    "cannot write {}: it exists and is not a directory",
                    path.display()
                );
            }
            return Ok(Self {
                path: real,
                created: Vec::new(),
            });
        }
        let mut missing: Vec<&Path> = real
            .ancestors()
            .filter(|a| !a.as_os_str().is_empty())
            .take_while(|a| std::fs::symlink_metadata(a).is_err())
            .collect();
        missing.reverse();
        let mut out = Self {
            path: real.clone(),
            created: Vec::new(),
        };
        for d in missing {
            cleanup::register(d);
            if let Err(e) = std::fs::create_dir(d) {
                cleanup::forget(d);
                return Err(e).with_context(|| format!("cannot create {}", path.display()));
            }
            out.created.push(d.to_path_buf());
        }
        Ok(out)
    }

    /// Reserve the file `name` in the directory in `set`.
    pub fn reserve(&self, set: &mut OutputSet, name: &str, origin: Origin) -> Result<usize> {
        set.reserve(&self.path.join(name), origin)
    }

    /// Keep the directory (after every file in it was committed).
    pub fn keep(mut self) {
        for d in std::mem::take(&mut self.created) {
            cleanup::forget(&d);
        }
    }
}

impl Drop for OutDir {
    fn drop(&mut self) {
        for d in self.created.iter().rev() {
            let _ = std::fs::remove_dir(d);
            cleanup::forget(d);
        }
    }
}

/// Image formats by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit sRGB PNG.
    Png,
    /// Linear float OpenEXR.
    Exr,
}

/// The format named by `path`'s extension.
pub fn image_format(path: &Path) -> Result<ImageFormat> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("png") => Ok(ImageFormat::Png),
        Some("exr") => Ok(ImageFormat::Exr),
        _ => bail!(
            "cannot write {}: the output must end in .png or .exr",
            path.display()
        ),
    }
}

/// Encode `image` in memory, with the number of pixels clamped to fit the format (EXR: beyond
/// the `f32` range; PNG clamps to [0, 1] by design and reports 0).
pub fn encode_counting(image: &Image, format: ImageFormat) -> Result<(Vec<u8>, usize)> {
    Ok(match format {
        ImageFormat::Png => (raytree::codec::png(image)?, 0),
        ImageFormat::Exr => raytree::codec::exr_clamped(image)?,
    })
}

/// Encode 8-bit RGB bytes as PNG in memory.
pub fn encode_rgb8_png(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>> {
    Ok(raytree::codec::png_rgb8(rgb, width, height)?)
}

/// Largest image file `compare`, `outliers` and `converge --reference` read (1 GiB).
pub const MAX_IMAGE_BYTES: u64 = 1 << 30;

/// Read a PNG (sRGB, decoded to linear) or EXR (linear) into an [`Image`].
pub fn read_image(path: &Path) -> Result<Image> {
    let format = image_format(path)
        .map_err(|_| anyhow::anyhow!("cannot read {}: expected .png or .exr", path.display()))?;
    // Only a regular file, size-bounded (a FIFO would block, a device never end); the decoder's
    // error is its own message only (its source repeats it).
    let shown = escape(path);
    let bytes = super::read::read_limited(path, MAX_IMAGE_BYTES)
        .map_err(|e| anyhow::anyhow!("cannot read image {shown}: {e}"))?;
    let kind = match format {
        ImageFormat::Png => image::ImageFormat::Png,
        ImageFormat::Exr => image::ImageFormat::OpenExr,
    };
    let img = image::load_from_memory_with_format(&bytes, kind)
        .map_err(|e| anyhow::anyhow!("cannot read image {shown}: {e}"))?;
    drop(bytes);
    let (width, height) = (img.width(), img.height());
    let pixels = match format {
        ImageFormat::Exr => img
            .into_rgb32f()
            .pixels()
            .map(|p| {
                raytree::math::Rgb::new(f64::from(p.0[0]), f64::from(p.0[1]), f64::from(p.0[2]))
            })
            .collect(),
        ImageFormat::Png => img
            .into_rgb8()
            .pixels()
            .map(|p| {
                raytree::math::Rgb::from_array(
                    p.0.map(|c| raytree::math::srgb_to_linear(f64::from(c) / 255.0)),
                )
            })
            .collect(),
    };
    Ok(Image {
        width,
        height,
        pixels,
    })
}
