//! Image files: binary PPM (P6) and PNG, 8-bit RGB, written atomically (to a
//! temporary file in the same directory, renamed over the target at the end),
//! so a failed or interrupted render never leaves a partial image; or written
//! to standard output (`-o -`).
//!
//! A part of a frame (`render --region`) carries where it belongs, so that
//! `raypack stitch` can check and assemble the parts: one line of text,
//! `raypack-region x=X y=Y w=W h=H full=FWxFH render=HASH`, as the PNG
//! `tEXt` chunk with keyword `raypack-region` (text from `x=`), or as the
//! PPM comment line `# raypack-region …` right after `P6`. `render` is the
//! FNV-1a hash (8 hex digits) of the scene text and of every option that
//! changes the bytes: parts of different renders do not stitch.

use crate::Failure;
use raypack::camera::Rect;
use raypack::prelude::Rgb8;
use std::io::Write;
use std::path::{Path, PathBuf};
use tempfile::NamedTempFile;

/// Output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Binary PPM, `P6`, maxval 255.
    Ppm,
    /// PNG, 8-bit RGB.
    Png,
}

impl Format {
    /// The format named by the path's extension, if it names one.
    pub fn of_path(path: &Path) -> Option<Format> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("ppm") => Some(Format::Ppm),
            Some("png") => Some(Format::Png),
            _ => None,
        }
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Format::Ppm => "ppm",
            Format::Png => "png",
        }
    }
}

/// Where a part lies in its frame, and which render it is of.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Region {
    /// The rectangle of the full image.
    pub rect: Rect,
    /// The full image's size.
    pub full: (u32, u32),
    /// Hash of the scene and the byte-changing options (8 hex digits).
    pub render: String,
}

/// The keyword of the PNG text chunk and PPM comment.
pub const REGION_KEY: &str = "raypack-region";

impl Region {
    /// The text after the keyword.
    pub fn text(&self) -> String {
        let r = self.rect;
        format!("x={} y={} w={} h={} full={}x{} render={}", r.x, r.y, r.w, r.h, self.full.0, self.full.1, self.render)
    }

    /// Reads [`Region::text`] back.
    pub fn parse(text: &str) -> Option<Region> {
        let mut f = std::collections::HashMap::new();
        for field in text.split_whitespace() {
            let (k, v) = field.split_once('=')?;
            f.insert(k, v);
        }
        let num = |k: &str| f.get(k)?.parse::<u32>().ok();
        let (fw, fh) = f.get("full")?.split_once('x')?;
        let rect = Rect { x: num("x")?, y: num("y")?, w: num("w")?, h: num("h")? };
        Some(Region { rect, full: (fw.parse().ok()?, fh.parse().ok()?), render: f.get("render")?.to_string() })
    }
}

/// Where an image goes.
pub enum Sink {
    /// A file, written atomically.
    File(PendingImage),
    /// Standard output.
    Stdout(Format),
}

impl Sink {
    /// `path` (`-`: standard output) in `format` (`None`: the extension's;
    /// standard output defaults to PPM). Files are created now, so an
    /// unwritable location fails before any rendering; `no_clobber` makes
    /// an existing file an error, now and when renaming into place.
    pub fn create(path: &Path, format: Option<Format>, no_clobber: bool) -> Result<Sink, Failure> {
        if path.as_os_str() == "-" {
            return Ok(Sink::Stdout(format.unwrap_or(Format::Ppm)));
        }
        let format = match (Format::of_path(path), format) {
            (Some(a), Some(b)) if a != b => {
                return Err(Failure(format!(
                    "{}: the extension says {} but --format says {}",
                    path.display(),
                    a.name(),
                    b.name()
                )))
            }
            (Some(f), _) | (None, Some(f)) => f,
            (None, None) => {
                return Err(Failure(format!(
                    "{}: unknown output format (use a .ppm or .png file name, or --format)",
                    path.display()
                )))
            }
        };
        if no_clobber && path.exists() {
            return Err(Failure(format!(
                "{}: already exists (use --force to overwrite it, or -o to name the output)",
                path.display()
            )));
        }
        PendingImage::create(path, format, no_clobber).map(Sink::File)
    }

    /// What the summary calls it.
    pub fn name(&self) -> String {
        match self {
            Sink::File(p) => p.target.display().to_string(),
            Sink::Stdout(_) => "standard output".into(),
        }
    }

    /// Encodes the image (with `region` if given) and puts it in place.
    pub fn finish(self, width: u32, height: u32, pixels: &[Rgb8], region: Option<&Region>) -> Result<(), Failure> {
        match self {
            Sink::File(p) => p.finish(width, height, pixels, region),
            Sink::Stdout(format) => {
                let mut w = std::io::BufWriter::new(std::io::stdout().lock());
                let done = encode(&mut w, format, width, height, pixels, region).and_then(|()| Ok(w.flush()?));
                match done {
                    // The reader went away (`raypack render … -o - | head`):
                    // it wanted no more, so end quietly, as Unix tools do.
                    Err(e) if is_broken_pipe(&*e) => Ok(()),
                    Err(e) => Err(Failure(format!("standard output: {e}"))),
                    Ok(()) => Ok(()),
                }
            }
        }
    }
}

/// An image file being written: a temporary file beside the target.
pub struct PendingImage {
    target: PathBuf,
    temp: NamedTempFile,
    format: Format,
    no_clobber: bool,
}

impl PendingImage {
    fn create(target: &Path, format: Format, no_clobber: bool) -> Result<PendingImage, Failure> {
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let temp = tempfile::Builder::new()
            .prefix(".raypack-")
            .suffix(".tmp")
            .tempfile_in(dir)
            .map_err(|e| Failure(format!("{}: cannot write here: {e}", target.display())))?;
        Ok(PendingImage { target: target.to_path_buf(), temp, format, no_clobber })
    }

    /// Encodes the image, then renames the file into place.
    fn finish(mut self, width: u32, height: u32, pixels: &[Rgb8], region: Option<&Region>) -> Result<(), Failure> {
        let err = |e: &dyn std::fmt::Display| Failure(format!("{}: {e}", self.target.display()));
        {
            let mut w = std::io::BufWriter::new(self.temp.as_file_mut());
            encode(&mut w, self.format, width, height, pixels, region).map_err(|e| err(&e))?;
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
        let done = if self.no_clobber { self.temp.persist_noclobber(&target) } else { self.temp.persist(&target) };
        done.map_err(|e| Failure(format!("{}: {}", target.display(), e.error)))?;
        Ok(())
    }
}

/// Writes `text` to standard output. `Ok(false)`: the reader has closed the
/// pipe (`raypack bench … | head -1`) and wants no more, so the caller stops
/// printing and ends quietly (exit 0), as Unix tools do; any other write
/// error is a failure.
pub fn print(text: &str) -> Result<bool, Failure> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(false),
        Err(e) => Err(Failure(format!("standard output: {e}"))),
    }
}

/// Whether `e` (or what it wraps: the PNG encoder's I/O error) is a write
/// to a pipe whose reader has closed it.
fn is_broken_pipe(e: &(dyn std::error::Error + 'static)) -> bool {
    let mut at = Some(e);
    while let Some(e) = at {
        let io = match e.downcast_ref::<png::EncodingError>() {
            Some(png::EncodingError::IoError(io)) => Some(io),
            _ => e.downcast_ref::<std::io::Error>(),
        };
        if io.is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe) {
            return true;
        }
        at = e.source();
    }
    false
}

fn encode(
    w: &mut impl Write,
    format: Format,
    width: u32,
    height: u32,
    pixels: &[Rgb8],
    region: Option<&Region>,
) -> Result<(), Box<dyn std::error::Error>> {
    match format {
        Format::Ppm => write_ppm(w, width, height, pixels, region)?,
        Format::Png => write_png(w, width, height, pixels, region)?,
    }
    Ok(())
}

/// Binary PPM: `P6\n[# raypack-region …\n]<w> <h>\n255\n` then RGB bytes,
/// rows top to bottom.
pub fn write_ppm(
    w: &mut impl Write,
    width: u32,
    height: u32,
    pixels: &[Rgb8],
    region: Option<&Region>,
) -> std::io::Result<()> {
    w.write_all(b"P6\n")?;
    if let Some(r) = region {
        writeln!(w, "# {REGION_KEY} {}", r.text())?;
    }
    write!(w, "{width} {height}\n255\n")?;
    w.write_all(pixels.as_flattened())
}

/// 8-bit RGB PNG (with a `raypack-region` text chunk for a part), with
/// the fast compression: the balanced one costs a 512² render a third of
/// its whole process for files 15–35 % smaller (docs/cli.md).
pub fn write_png(
    w: &mut impl Write,
    width: u32,
    height: u32,
    pixels: &[Rgb8],
    region: Option<&Region>,
) -> Result<(), png::EncodingError> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    if let Some(r) = region {
        enc.add_text_chunk(REGION_KEY.into(), r.text())?;
    }
    let mut writer = enc.write_header()?;
    writer.write_image_data(pixels.as_flattened())?;
    writer.finish()
}

/// A decoded image file: size, pixels and its region, if it has one.
pub struct Decoded {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
    pub region: Option<Region>,
}

/// Reads a PPM (P6, maxval 255) or 8-bit RGB PNG, as `raypack render`
/// writes them.
pub fn read_image(bytes: &[u8]) -> Result<Decoded, String> {
    if bytes.starts_with(b"\x89PNG") {
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().map_err(|e| e.to_string())?;
        let info = reader.info();
        if (info.color_type, info.bit_depth) != (png::ColorType::Rgb, png::BitDepth::Eight) {
            return Err("not an 8-bit RGB PNG".into());
        }
        let region = info
            .uncompressed_latin1_text
            .iter()
            .find(|t| t.keyword == REGION_KEY)
            .map(|t| Region::parse(&t.text).ok_or(format!("malformed {REGION_KEY} text `{}`", t.text)))
            .transpose()?;
        let (width, height) = (info.width, info.height);
        let size = reader.output_buffer_size().ok_or("image too large")?;
        let mut pixels = vec![0; size];
        let frame = reader.next_frame(&mut pixels).map_err(|e| e.to_string())?;
        pixels.truncate(frame.buffer_size());
        return Ok(Decoded { width, height, pixels, region });
    }
    if !bytes.starts_with(b"P6") {
        return Err("neither a PNG nor a binary PPM (P6) file".into());
    }
    // Header: P6, then width, height, maxval separated by whitespace, with
    // `#` comments to the end of a line; one whitespace byte before the data.
    let mut at = 2;
    let mut region = None;
    let mut fields = Vec::new();
    while fields.len() < 3 {
        match bytes.get(at) {
            None => return Err("PPM header ends early".into()),
            Some(b'#') => {
                let end = bytes[at..].iter().position(|&b| b == b'\n').map_or(bytes.len(), |i| at + i);
                let comment = String::from_utf8_lossy(&bytes[at + 1..end]);
                if let Some(text) = comment.trim().strip_prefix(REGION_KEY) {
                    region = Some(
                        Region::parse(text).ok_or(format!("malformed {REGION_KEY} comment `{}`", comment.trim()))?,
                    );
                }
                at = end;
            }
            Some(b) if b.is_ascii_whitespace() => at += 1,
            Some(_) => {
                let end = bytes[at..].iter().position(|b| !b.is_ascii_digit()).map_or(bytes.len(), |i| at + i);
                let v = std::str::from_utf8(&bytes[at..end])
                    .ok()
                    .and_then(|s| s.parse::<u32>().ok())
                    .ok_or("bad number in the PPM header")?;
                fields.push(v);
                at = end;
            }
        }
    }
    if fields[2] != 255 {
        return Err(format!("PPM maxval {} (only 255 is read)", fields[2]));
    }
    let data = bytes.get(at + 1..).unwrap_or(&[]);
    let need = fields[0] as usize * fields[1] as usize * 3;
    if data.len() != need {
        return Err(format!("{} bytes of pixels for a {}x{} image (needs {need})", data.len(), fields[0], fields[1]));
    }
    Ok(Decoded { width: fields[0], height: fields[1], pixels: data.to_vec(), region })
}
