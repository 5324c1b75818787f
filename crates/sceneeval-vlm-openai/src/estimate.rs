//! What a request costs before it is sent: an estimate of its input tokens, for pacing under a
//! tokens-per-minute limit and for `sceneeval evaluate --dry-run`.

use sceneeval_vlm::VlmRequest;

use crate::ImageDetail;

/// Characters per token of the text estimate: OpenAI's rule of thumb for English text.
pub const CHARS_PER_TOKEN: u64 = 4;

/// Tokens of an image sent with `detail: low` (and the base of a `high` one), OpenAI's figure
/// for GPT-4o.
pub const LOW_DETAIL_IMAGE_TOKENS: u64 = 85;

/// Tokens per 512-pixel tile of an image sent with `detail: high` (GPT-4o).
pub const HIGH_DETAIL_TILE_TOKENS: u64 = 170;

/// The tokens OpenAI counts for an image of `width` x `height` pixels at `detail`, by its
/// published rule for GPT-4o:
///
/// - `low`: 85 tokens, whatever the size;
/// - `high`: the image is scaled down to fit in 2048 x 2048, then down so that its shorter side
///   is at most 768 pixels (a smaller image is not enlarged); each 512-pixel tile needed to cover
///   it costs 170 tokens, plus 85;
/// - `auto`: the server chooses; estimated as `high` (an upper bound).
///
/// ```
/// use sceneeval_vlm_openai::{ImageDetail, image_tokens};
/// assert_eq!(image_tokens(4096, 8192, ImageDetail::Low), 85);
/// // 1024 x 1024 -> 768 x 768: 2 x 2 tiles, 85 + 4 * 170 = 765 (OpenAI's example).
/// assert_eq!(image_tokens(1024, 1024, ImageDetail::High), 765);
/// // 2048 x 4096 -> 1024 x 2048 -> 768 x 1536: 2 x 3 tiles, 85 + 6 * 170 = 1105 (OpenAI's).
/// assert_eq!(image_tokens(2048, 4096, ImageDetail::High), 1105);
/// // 512 x 512 stays: one tile, 85 + 170 = 255.
/// assert_eq!(image_tokens(512, 512, ImageDetail::Auto), 255);
/// ```
pub fn image_tokens(width: u32, height: u32, detail: ImageDetail) -> u64 {
    if detail == ImageDetail::Low || width == 0 || height == 0 {
        return LOW_DETAIL_IMAGE_TOKENS;
    }
    let (mut w, mut h) = (f64::from(width), f64::from(height));
    let fit = (2048.0 / w.max(h)).min(1.0);
    w *= fit;
    h *= fit;
    let short = (768.0 / w.min(h)).min(1.0);
    w *= short;
    h *= short;
    // Rounded to whole pixels first, so that 768.0000001 is not a third tile.
    let tiles = |side: f64| (side.round() as u64).div_ceil(512).max(1);
    LOW_DETAIL_IMAGE_TOKENS + HIGH_DETAIL_TILE_TOKENS * tiles(w) * tiles(h)
}

/// The input tokens of `request` sent with image `detail`, estimated: the characters of the
/// system prompt, the user text and the response schema (compact JSON, which OpenAI adds to the
/// prompt for structured output) divided by [`CHARS_PER_TOKEN`] and rounded up, plus
/// [`image_tokens`] for each image. The server's own count differs by the tokenizer and a few
/// tokens of message framing; the estimate is for pacing and for planning a run, never billed.
///
/// ```
/// use sceneeval_vlm::{ResponseSchema, VlmRequest, check::test_image};
/// use sceneeval_vlm_openai::{ImageDetail, estimate_prompt_tokens};
/// let request = VlmRequest {
///     task: "t".into(),
///     system: "abcd".repeat(10),        // 40 characters
///     user_text: "x".repeat(41),        // 41 characters
///     images: vec![test_image(), test_image()],
///     schema: ResponseSchema { name: "t".into(), schema: serde_json::json!({}) }, // "{}": 2
/// };
/// // ceil((40 + 41 + 2) / 4) = ceil(20.75) = 21 text tokens, and 2 x 85 for the images.
/// assert_eq!(estimate_prompt_tokens(&request, ImageDetail::Low), 21 + 170);
/// ```
pub fn estimate_prompt_tokens(request: &VlmRequest, detail: ImageDetail) -> u64 {
    let chars = request.system.chars().count()
        + request.user_text.chars().count()
        + request.schema.schema.to_string().chars().count();
    let text = (chars as u64).div_ceil(CHARS_PER_TOKEN);
    let images: u64 = request
        .images
        .iter()
        .map(|i| {
            let (w, h) = i.dimensions();
            image_tokens(w, h, detail)
        })
        .sum();
    text + images
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_tokens_by_hand() {
        // 4096 x 8192 high: fit 2048 -> 1024 x 2048, short side 768 -> 768 x 1536: 2 x 3 tiles,
        // 85 + 6 * 170 = 1105.
        assert_eq!(image_tokens(4096, 8192, ImageDetail::High), 1105);
        // 513 x 500 high: nothing scaled (both under 768): 2 x 1 tiles, 85 + 340 = 425.
        assert_eq!(image_tokens(513, 500, ImageDetail::High), 425);
        // 800 x 600 high: short side 600 <= 768, not scaled: 2 x 2 tiles: 765.
        assert_eq!(image_tokens(800, 600, ImageDetail::High), 765);
        // 3000 x 1000 high: fit 2048 -> 2048 x 682.67; short side under 768: 4 x 2 tiles,
        // 85 + 8 * 170 = 1445.
        assert_eq!(image_tokens(3000, 1000, ImageDetail::High), 1445);
        // 64 x 64 (the test views) high: one tile, 255; low 85.
        assert_eq!(image_tokens(64, 64, ImageDetail::High), 255);
        assert_eq!(image_tokens(64, 64, ImageDetail::Low), 85);
    }
}
