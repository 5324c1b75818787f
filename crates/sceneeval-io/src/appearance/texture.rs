//! Decoding texture images and bounding their size.

use std::io::Cursor;

use image::imageops::FilterType;
use image::{ImageReader, Limits, Rgba32FImage, RgbaImage};

use super::Texture;

/// Largest texture side kept, in texels; larger images are downscaled (in linear light) at
/// load. A 512-pixel render never shows more than this.
pub const MAX_TEXTURE_DIMENSION: u32 = 1024;

/// Largest image side accepted by the decoder at all.
const MAX_DECODED_DIMENSION: u32 = 16_384;

/// Largest allocation the decoder may make for one image (bytes).
const MAX_DECODE_ALLOC: u64 = 1 << 30;

/// Decodes PNG or JPEG `bytes` into an sRGB RGBA8 texture of at most
/// [`MAX_TEXTURE_DIMENSION`] texels per side.
pub(super) fn decode(label: String, bytes: &[u8]) -> Result<Texture, String> {
    let mut reader = ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read the image: {e}"))?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_DECODED_DIMENSION);
    limits.max_image_height = Some(MAX_DECODED_DIMENSION);
    limits.max_alloc = Some(MAX_DECODE_ALLOC);
    reader.limits(limits);
    if reader.format().is_none() {
        return Err("unknown image format (PNG and JPEG are supported)".into());
    }
    let image = reader
        .decode()
        .map_err(|e| format!("cannot decode the image: {e}"))?
        .to_rgba8();
    let (width, height) = image.dimensions();
    if width == 0 || height == 0 {
        return Err("the image is empty".into());
    }
    let image = bounded(image);
    Ok(Texture {
        label,
        width: image.width(),
        height: image.height(),
        pixels: image.into_raw(),
    })
}

/// `image` scaled down so that neither side exceeds [`MAX_TEXTURE_DIMENSION`], averaging in
/// linear light (an sRGB average would darken contrasty textures).
fn bounded(image: RgbaImage) -> RgbaImage {
    let (w, h) = image.dimensions();
    let longest = w.max(h);
    if longest <= MAX_TEXTURE_DIMENSION {
        return image;
    }
    let scale = f64::from(MAX_TEXTURE_DIMENSION) / f64::from(longest);
    let nw = ((f64::from(w) * scale).round() as u32).clamp(1, MAX_TEXTURE_DIMENSION);
    let nh = ((f64::from(h) * scale).round() as u32).clamp(1, MAX_TEXTURE_DIMENSION);
    let linear = Rgba32FImage::from_fn(w, h, |x, y| {
        let p = image.get_pixel(x, y).0;
        image::Rgba([
            srgb_to_linear(p[0]),
            srgb_to_linear(p[1]),
            srgb_to_linear(p[2]),
            f32::from(p[3]) / 255.0,
        ])
    });
    let small = image::imageops::resize(&linear, nw, nh, FilterType::Triangle);
    tracing::debug!(from = ?(w, h), to = ?(nw, nh), "texture downscaled");
    RgbaImage::from_fn(nw, nh, |x, y| {
        let p = small.get_pixel(x, y).0;
        image::Rgba([
            linear_to_srgb(p[0]),
            linear_to_srgb(p[1]),
            linear_to_srgb(p[2]),
            (p[3].clamp(0.0, 1.0) * 255.0).round() as u8,
        ])
    })
}

/// The sRGB transfer function's inverse: an encoded byte to linear light in `[0, 1]`.
///
/// ```
/// use sceneeval_io::appearance::{linear_to_srgb, srgb_to_linear};
/// assert_eq!(srgb_to_linear(255), 1.0);
/// // Half the light is sRGB 0.7354: byte 188.
/// assert_eq!(linear_to_srgb(0.5), 188);
/// assert_eq!(linear_to_srgb(srgb_to_linear(77)), 77);
/// ```
pub fn srgb_to_linear(v: u8) -> f32 {
    let c = f32::from(v) / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light in `[0, 1]` (clamped) to an sRGB-encoded byte (see [`srgb_to_linear`]).
pub fn linear_to_srgb(v: f32) -> u8 {
    let c = v.clamp(0.0, 1.0);
    let e = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
        let img = RgbaImage::from_fn(w, h, |x, y| image::Rgba(f(x, y)));
        let mut out = Vec::new();
        img.write_to(&mut Cursor::new(&mut out), image::ImageFormat::Png)
            .unwrap();
        out
    }

    #[test]
    fn small_images_are_kept_texel_for_texel() {
        let t = decode(
            "t".into(),
            &png(3, 2, |x, y| [x as u8 * 80, y as u8 * 200, 7, 255]),
        )
        .unwrap();
        assert_eq!((t.width, t.height), (3, 2));
        // Texel (2, 1) is the sixth: bytes 20..24.
        assert_eq!(&t.pixels[20..24], &[160, 200, 7, 255]);
    }

    #[test]
    fn large_images_are_downscaled_in_linear_light() {
        // A 2048 x 1024 checkerboard of black and white texels averages, in linear light, to
        // 0.5, which is sRGB 0.7354 -> byte 188 (an sRGB average would give 128).
        let t = decode(
            "big".into(),
            &png(2048, 1024, |x, y| {
                if (x + y) % 2 == 0 {
                    [255; 4]
                } else {
                    [0, 0, 0, 255]
                }
            }),
        )
        .unwrap();
        assert_eq!((t.width, t.height), (1024, 512));
        let centre = ((256 * 1024 + 512) * 4) as usize;
        let v = t.pixels[centre];
        assert!((186..=190).contains(&v), "{v}");
        assert_eq!(t.pixels[centre + 3], 255);
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        assert!(decode("x".into(), b"not an image").is_err());
        assert!(decode("x".into(), b"\x89PNG\r\n\x1a\n broken").is_err());
        assert!(decode("x".into(), &[]).is_err());
    }

    #[test]
    fn transfer_functions_round_trip() {
        for v in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(v)), v);
        }
    }
}
