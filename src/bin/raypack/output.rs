//! Image files: binary PPM (P6) and PNG, 8-bit RGB, written atomically (to a
//! temporary file in the same directory, renamed over the target at the end),
//! so a failed or interrupted render never leaves a partial image.

use crate::Failure;
use raypack::prelude::Rgb8;
use std::io::Write;
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// Output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Binary PPM, `P6`, maxval 255.
    Ppm,
    /// PNG, 8-bit RGB.
    Png,
}

impl Format {
    /// The format named by the path's extension.
    pub fn from_path(path: &Path) -> Result<Format, Failure> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("ppm") => Ok(Format::Ppm),
            Some("png") => Ok(Format::Png),
            _ => Err(Failure(format!("{}: unknown output format (use a .ppm or .png file name)", path.display()))),
        }
    }
}

/// An image file being written: a temporary file beside the target.
pub struct PendingImage {
    target: PathBuf,
    temp: NamedTempFile,
    format: Format,
}

impl PendingImage {
    /// Creates the temporary file now, so an unwritable location fails before
    /// any rendering.
    pub fn create(target: &Path) -> Result<PendingImage, Failure> {
        let format = Format::from_path(target)?;
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let temp = tempfile::Builder::new()
            .prefix(".raypack-")
            .suffix(".tmp")
            .tempfile_in(dir)
            .map_err(|e| Failure(format!("{}: cannot write here: {e}", target.display())))?;
        Ok(PendingImage { target: target.to_path_buf(), temp, format })
    }

    /// Encodes the image, then renames the file into place.
    pub fn finish(mut self, width: u32, height: u32, pixels: &[Rgb8]) -> Result<(), Failure> {
        let err = |e: &dyn std::fmt::Display| Failure(format!("{}: {e}", self.target.display()));
        {
            let mut w = std::io::BufWriter::new(self.temp.as_file_mut());
            match self.format {
                Format::Ppm => write_ppm(&mut w, width, height, pixels).map_err(|e| err(&e))?,
                Format::Png => write_png(&mut w, width, height, pixels).map_err(|e| err(&e))?,
            }
            w.flush().map_err(|e| err(&e))?;
        }
        self.temp.as_file().sync_all().map_err(|e| err(&e))?;
        // Temporary files are created with mode 0600; images are ordinary files.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let _ = self.temp.as_file().set_permissions(std::fs::Permissions::from_mode(0o644));
        }
        let target = self.target.clone();
        self.temp.persist(&target).map_err(|e| Failure(format!("{}: {}", target.display(), e.error)))?;
        Ok(())
    }
}

/// Binary PPM: `P6\n<w> <h>\n255\n` then RGB bytes, rows top to bottom.
pub fn write_ppm(w: &mut impl Write, width: u32, height: u32, pixels: &[Rgb8]) -> std::io::Result<()> {
    write!(w, "P6\n{width} {height}\n255\n")?;
    w.write_all(pixels.as_flattened())
}

/// 8-bit RGB PNG.
pub fn write_png(w: &mut impl Write, width: u32, height: u32, pixels: &[Rgb8]) -> Result<(), png::EncodingError> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header()?;
    writer.write_image_data(pixels.as_flattened())?;
    writer.finish()
}
