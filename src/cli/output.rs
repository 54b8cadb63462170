//! Output files that appear whole or not at all: write to a temporary file beside the target,
//! rename on success, remove on failure. Unwritable targets fail before any work is done.

use anyhow::{Context, Result, bail};
use raytree::Image;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A reserved output path; dropping it without [`Pending::commit`] leaves no file behind.
pub struct Pending {
    target: PathBuf,
    temp: PathBuf,
    file: Option<File>,
}

impl Pending {
    /// Reserve `target` by creating a temporary file in its directory.
    pub fn create(target: &Path) -> Result<Self> {
        let name = target
            .file_name()
            .with_context(|| format!("cannot write {}: not a file name", target.display()))?;
        if target.is_dir() {
            bail!("cannot write {}: it is a directory", target.display());
        }
        let dir = target
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let temp = dir.join(format!(
            ".{}.{}.tmp",
            name.to_string_lossy(),
            std::process::id()
        ));
        let file =
            File::create(&temp).with_context(|| format!("cannot write {}", target.display()))?;
        Ok(Self {
            target: target.to_path_buf(),
            temp,
            file: Some(file),
        })
    }

    /// Write `bytes` and move the file into place.
    pub fn commit(mut self, bytes: &[u8]) -> Result<()> {
        let mut file = self.file.take().expect("not yet committed");
        file.write_all(bytes)
            .and_then(|()| file.sync_all())
            .with_context(|| format!("cannot write {}", self.target.display()))?;
        drop(file);
        std::fs::rename(&self.temp, &self.target)
            .with_context(|| format!("cannot write {}", self.target.display()))?;
        self.temp = PathBuf::new();
        Ok(())
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if !self.temp.as_os_str().is_empty() {
            let _ = std::fs::remove_file(&self.temp);
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

/// Encode `image` in memory.
pub fn encode(image: &Image, format: ImageFormat) -> Result<Vec<u8>> {
    Ok(match format {
        ImageFormat::Png => raytree::codec::png(image)?,
        ImageFormat::Exr => raytree::codec::exr(image)?,
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
