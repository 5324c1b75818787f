//! Pixel work on the CPU: reading padded rows back from the GPU, un-premultiplying alpha, and
//! texture mipmaps. Everything here is exact integer or fixed floating-point arithmetic, so
//! results do not depend on the driver.

use std::sync::OnceLock;

use image::RgbaImage;

use sceneeval_io::appearance::{linear_to_srgb, srgb_to_linear};

use crate::RenderError;

/// Bytes per row of a readback buffer: `4 * width` rounded up to wgpu's 256-byte copy
/// alignment.
///
/// ```
/// # use sceneeval_render::padded_row_bytes;
/// assert_eq!(padded_row_bytes(64), 256);
/// assert_eq!(padded_row_bytes(65), 512); // 260 bytes of pixels, padded
/// assert_eq!(padded_row_bytes(1), 256);
/// ```
pub fn padded_row_bytes(width: u32) -> u32 {
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    (4 * width).div_ceil(align) * align
}

/// Maps `buffer` (rows of `padded_row` bytes) and returns the `width * height` RGBA pixels
/// without the padding.
pub(crate) fn read_padded(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    width: u32,
    height: u32,
    padded_row: u32,
    label: &str,
) -> Result<Vec<u8>, RenderError> {
    let fail = |message: String| RenderError::Readback {
        view: label.to_owned(),
        message,
    };
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        // The receiver waits below; a send can only fail if it is gone, and then nobody cares.
        let _ = tx.send(result);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| fail(format!("waiting for the GPU: {e}")))?;
    rx.recv()
        .map_err(|_| fail("the GPU never answered the map request".into()))?
        .map_err(|e| fail(format!("mapping the buffer: {e}")))?;
    let row = 4 * width as usize;
    let mut pixels = Vec::with_capacity(row * height as usize);
    {
        let data = slice
            .get_mapped_range()
            .map_err(|e| fail(format!("reading the mapped buffer: {e}")))?;
        for y in 0..height as usize {
            let start = y * padded_row as usize;
            let Some(src) = data.get(start..start + row) else {
                return Err(fail(format!("row {y} lies outside the buffer")));
            };
            pixels.extend_from_slice(src);
        }
    }
    buffer.unmap();
    Ok(pixels)
}

/// sRGB byte to linear light, for every byte.
fn decode_table() -> &'static [f32; 256] {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|v| srgb_to_linear(v as u8)))
}

/// Turns the renderer's premultiplied-alpha pixels (sRGB-encoded premultiplied colour) into
/// the straight alpha a PNG stores: edge pixels that multisampling blended with the
/// transparent background get their full colour back instead of a dark fringe. Fully
/// transparent pixels become `0, 0, 0, 0`.
pub(crate) fn unpremultiply(image: &mut RgbaImage) {
    let table = decode_table();
    for p in image.pixels_mut() {
        let a = p.0[3];
        match a {
            255 => {}
            0 => p.0 = [0; 4],
            _ => {
                let alpha = f32::from(a) / 255.0;
                for c in &mut p.0[..3] {
                    *c = linear_to_srgb(table[usize::from(*c)] / alpha);
                }
            }
        }
    }
}

/// The mipmap chain of an sRGB RGBA8 image, level 0 first: each level halves the previous one
/// (rounding down, at least 1 texel), averaging 2 x 2 texels in linear light (alpha
/// linearly).
pub(crate) fn mip_chain(width: u32, height: u32, pixels: &[u8]) -> Vec<(u32, u32, Vec<u8>)> {
    let table = decode_table();
    let mut levels = vec![(width, height, pixels.to_vec())];
    while let Some((w, h, prev)) = levels.last() {
        let (w, h) = (*w, *h);
        if w == 1 && h == 1 {
            break;
        }
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let mut next = Vec::with_capacity((nw * nh * 4) as usize);
        for y in 0..nh {
            for x in 0..nw {
                let mut sum = [0.0f32; 4];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (2 * x + dx).min(w - 1);
                    let sy = (2 * y + dy).min(h - 1);
                    let i = ((sy * w + sx) * 4) as usize;
                    for k in 0..3 {
                        sum[k] += table[usize::from(prev[i + k])];
                    }
                    sum[3] += f32::from(prev[i + 3]);
                }
                next.extend_from_slice(&[
                    linear_to_srgb(sum[0] / 4.0),
                    linear_to_srgb(sum[1] / 4.0),
                    linear_to_srgb(sum[2] / 4.0),
                    (sum[3] / 4.0).round() as u8,
                ]);
            }
        }
        levels.push((nw, nh, next));
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unpremultiply_restores_edge_colours() {
        // A pure red pixel half covered: premultiplied linear (0.5, 0, 0) is sRGB 0.7354 ->
        // byte 188 with alpha 128 (0.50196). Byte 188 decodes to 0.5029 linear;
        // 0.5029 / 0.50196 = 1.0018, clamped to 1 -> 255.
        let mut img = RgbaImage::from_raw(3, 1, vec![188, 0, 0, 128, 10, 20, 30, 255, 9, 9, 9, 0]).unwrap();
        unpremultiply(&mut img);
        assert_eq!(img.get_pixel(0, 0).0, [255, 0, 0, 128]);
        assert_eq!(img.get_pixel(1, 0).0, [10, 20, 30, 255]);
        assert_eq!(img.get_pixel(2, 0).0, [0, 0, 0, 0]);
    }

    #[test]
    fn mips_average_in_linear_light_down_to_one_texel() {
        // 3 x 2: black and white columns. Level 1 is 1 x 1: texels (0,0), (1,0), (0,1), (1,1)
        // = white, black, white, black -> linear 0.5 -> sRGB 188.
        let w = [255, 255, 255, 255];
        let b = [0, 0, 0, 255];
        let px: Vec<u8> = [w, b, w, w, b, w].concat();
        let chain = mip_chain(3, 2, &px);
        assert_eq!(chain.len(), 2);
        assert_eq!((chain[1].0, chain[1].1), (1, 1));
        assert_eq!(chain[1].2, vec![188, 188, 188, 255]);
        let big = mip_chain(8, 2, &[7; 64]);
        let sizes: Vec<_> = big.iter().map(|l| (l.0, l.1)).collect();
        assert_eq!(sizes, [(8, 2), (4, 1), (2, 1), (1, 1)]);
    }

    #[test]
    fn rows_are_padded_to_256_bytes() {
        for (w, p) in [
            (1, 256),
            (63, 256),
            (64, 256),
            (65, 512),
            (97, 512),
            (512, 2048),
            (513, 2304),
        ] {
            assert_eq!(padded_row_bytes(w), p, "{w}");
        }
    }
}
