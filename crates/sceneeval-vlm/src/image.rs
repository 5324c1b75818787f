//! PNG images sent with a request.

use std::fmt;
use std::path::Path;
use std::sync::Arc;

use crate::VlmError;

const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// The bytes of one PNG file, checked on construction, cheap to clone (shared).
///
/// Only the signature and the header chunk are checked (the image is not decoded); the
/// dimensions are read from the header. `Debug` shows the size and the content hash, never the
/// bytes.
///
/// ```
/// use sceneeval_vlm::PngImage;
/// let png = sceneeval_vlm::check::test_image();
/// assert_eq!(png.dimensions(), (64, 64));
/// assert!(PngImage::new(b"GIF89a".to_vec(), "a gif").is_err());
/// ```
#[derive(Clone, PartialEq, Eq)]
pub struct PngImage {
    bytes: Arc<[u8]>,
    width: u32,
    height: u32,
}

impl PngImage {
    /// Checks that `bytes` hold a PNG file. `what` names the image in the error.
    ///
    /// # Errors
    /// [`VlmError::NotPng`] when the signature or the header chunk is missing or the
    /// dimensions are zero.
    pub fn new(bytes: impl Into<Arc<[u8]>>, what: &str) -> Result<Self, VlmError> {
        let bytes: Arc<[u8]> = bytes.into();
        let not_png = |reason| VlmError::NotPng {
            what: what.to_owned(),
            len: bytes.len(),
            reason,
        };
        if bytes.len() < 8 || bytes[..8] != PNG_SIGNATURE {
            return Err(not_png("no PNG signature"));
        }
        // The first chunk must be IHDR: length 13, type, then width and height (big-endian).
        if bytes.len() < 33 || &bytes[12..16] != b"IHDR" {
            return Err(not_png("no IHDR header chunk"));
        }
        let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
        let (width, height) = (be(16), be(20));
        if width == 0 || height == 0 {
            return Err(not_png("zero width or height"));
        }
        Ok(PngImage { bytes, width, height })
    }

    /// Reads and checks a PNG file.
    ///
    /// # Errors
    /// [`VlmError::Io`] when the file cannot be read, [`VlmError::NotPng`] as [`PngImage::new`].
    pub fn from_path(path: impl AsRef<Path>) -> Result<Self, VlmError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| VlmError::io(path, e))?;
        PngImage::new(bytes, &path.display().to_string())
    }

    /// A zero-byte placeholder, for code paths that cannot happen but must not panic.
    pub(crate) fn empty() -> Self {
        PngImage {
            bytes: Arc::from(Vec::new()),
            width: 1,
            height: 1,
        }
    }

    /// The file's bytes.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// Width and height in pixels, from the header.
    pub fn dimensions(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The blake3 hash of the bytes, as 64 lowercase hex digits.
    pub fn blake3_hex(&self) -> String {
        blake3::hash(&self.bytes).to_hex().to_string()
    }
}

impl fmt::Debug for PngImage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PngImage")
            .field("len", &self.bytes.len())
            .field("width", &self.width)
            .field("height", &self.height)
            .field("blake3", &self.blake3_hex())
            .finish()
    }
}

/// Encodes 8-bit RGB pixels (row-major, `3 * width * height` bytes) as a PNG file.
///
/// # Errors
/// [`VlmError::InvalidTask`] when the pixel buffer does not match the dimensions.
pub fn encode_rgb_png(width: u32, height: u32, rgb: &[u8]) -> Result<PngImage, VlmError> {
    let expected = 3 * width as usize * height as usize;
    if rgb.len() != expected || expected == 0 {
        return Err(VlmError::invalid_task(
            "image",
            format!("{width}x{height} RGB needs {expected} bytes, got {}", rgb.len()),
        ));
    }
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let encoded = encoder
            .write_header()
            .and_then(|mut writer| writer.write_image_data(rgb).and_then(|()| writer.finish()));
        // Writing into a Vec cannot fail for a correctly sized buffer; report it if it does.
        encoded.map_err(|e| VlmError::invalid_task("image", format!("PNG encoding failed: {e}")))?;
    }
    PngImage::new(out, "encoded RGB image")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encodes_and_reads_header() {
        let png = encode_rgb_png(3, 2, &[255; 18]).unwrap();
        assert_eq!(png.dimensions(), (3, 2));
        assert_eq!(&png.bytes()[..8], &PNG_SIGNATURE);
        let debug = format!("{png:?}");
        assert!(debug.contains("width: 3") && debug.contains("blake3"), "{debug}");
        assert!(encode_rgb_png(3, 2, &[0; 17]).is_err());
    }

    #[test]
    fn rejects_non_png() {
        let err = PngImage::new(vec![0u8; 40], "front render").unwrap_err();
        assert!(err.to_string().contains("front render"), "{err}");
        let mut header_only = PNG_SIGNATURE.to_vec();
        header_only.extend_from_slice(&[0; 4]);
        header_only.extend_from_slice(b"IDAT");
        header_only.resize(40, 0);
        assert!(PngImage::new(header_only, "x").is_err());
    }
}
