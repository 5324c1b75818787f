//! The endpoint check: one small structured request with an image, to find out whether an
//! endpoint answers, follows a schema and sees images.

use std::sync::OnceLock;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::PngImage;
use crate::TaskKind;
use crate::image::encode_rgb_png;
use crate::names::name_list;
use crate::task::{Single, Task, Validation};

/// Retries after a failed attempt of the endpoint check, `sceneeval vlm check`'s default and
/// the check a run makes before its first scene: one, so that a dead endpoint is reported in
/// seconds rather than after a run's [`DEFAULT_MAX_RETRIES`](crate::DEFAULT_MAX_RETRIES)
/// backoffs.
pub const CHECK_MAX_RETRIES: u32 = 1;

/// The colours the check offers.
pub const COLOURS: [&str; 6] = ["red", "green", "blue", "yellow", "black", "white"];

name_list!(
    /// `colour` values of the endpoint check.
    ColourName => COLOURS.to_vec()
);

/// The colour of the square in [`test_image`].
pub const TEST_IMAGE_COLOUR: &str = "red";

/// The check image: a 64 x 64 PNG, white with a red 32 x 32 square in the middle. Generated
/// once per process (no file is shipped).
pub fn test_image() -> PngImage {
    static IMAGE: OnceLock<Option<PngImage>> = OnceLock::new();
    let image = IMAGE.get_or_init(|| {
        let (w, h) = (64u32, 64u32);
        let mut rgb = Vec::with_capacity(3 * 64 * 64);
        for y in 0..h {
            for x in 0..w {
                let inside = (16..48).contains(&x) && (16..48).contains(&y);
                rgb.extend_from_slice(if inside { &[220, 20, 20] } else { &[255, 255, 255] });
            }
        }
        encode_rgb_png(w, h, &rgb).ok()
    });
    // Encoding a fixed, correctly sized buffer into memory does not fail; should it ever, an
    // empty image keeps the check running and the wrong colour in the answer shows it.
    image.clone().unwrap_or_else(PngImage::empty)
}

/// The answer of the endpoint check as the model writes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct EndpointCheckResponse {
    /// One of [`COLOURS`] (the schema lists them).
    #[schemars(with = "ColourName")]
    pub colour: String,
    /// Why.
    pub reason: String,
}

/// The endpoint check task: "what colour is the square?" about [`test_image`].
#[derive(Debug, Clone)]
pub struct EndpointCheck {
    image: PngImage,
}

impl Default for EndpointCheck {
    fn default() -> Self {
        EndpointCheck::new()
    }
}

impl EndpointCheck {
    /// The check with [`test_image`].
    pub fn new() -> Self {
        EndpointCheck { image: test_image() }
    }
}

/// A validated check answer.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct CheckAnswer {
    /// The colour the model saw.
    pub colour: String,
    /// Whether it is the colour of the square ([`TEST_IMAGE_COLOUR`]); a wrong colour usually
    /// means the model did not get the image (a text-only model, or a server that drops
    /// images).
    pub correct: bool,
    /// The model's reason.
    pub reason: String,
}

impl Task for EndpointCheck {
    type Response = EndpointCheckResponse;
    type Key = Single;
    type Item = CheckAnswer;

    fn kind(&self) -> TaskKind {
        TaskKind::EndpointCheck
    }

    fn images(&self) -> Vec<PngImage> {
        vec![self.image.clone()]
    }

    fn keys(&self) -> Vec<Single> {
        vec![Single]
    }

    fn validate(&self, r: EndpointCheckResponse, out: &mut Validation<Single, CheckAnswer>) {
        let colour = r.colour.trim().to_ascii_lowercase();
        if !COLOURS.contains(&colour.as_str()) {
            out.problem(
                Single,
                format!("colour {:?} is not one of {}", r.colour, COLOURS.join(", ")),
            );
            return;
        }
        out.answer(
            Single,
            CheckAnswer {
                correct: colour == TEST_IMAGE_COLOUR,
                colour,
                reason: r.reason,
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn test_image_is_deterministic() {
        let a = test_image();
        assert_eq!(a.dimensions(), (64, 64));
        assert_eq!(a, test_image());
    }
}
