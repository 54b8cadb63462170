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

    /// Reserve the file `name` in the directory.
    pub fn file(&self, name: &str, inputs: &Inputs) -> Result<Pending> {
        Pending::create(&self.path.join(name), inputs)
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

/// Read a PNG (sRGB, decoded to linear) or EXR (linear) into an [`Image`].
pub fn read_image(path: &Path) -> Result<Image> {
    let format = image_format(path)
        .map_err(|_| anyhow::anyhow!("cannot read {}: expected .png or .exr", path.display()))?;
    let img = image::open(path).with_context(|| format!("cannot read image {}", path.display()))?;
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
