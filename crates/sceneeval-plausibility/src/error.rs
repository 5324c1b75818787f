use std::path::PathBuf;

use thiserror::Error;

/// What was wrong with the input of a plausibility metric.
///
/// Variants name the metric and parameter (or the file) at fault. Geometry problems of the scene
/// itself cannot occur here: a [`sceneeval_scene::Scene`] is validated when it is built.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PlausibilityError {
    /// A parameter is out of its documented range (negative width, NaN, zero resolution, ...).
    #[error("{metric} parameter `{name}` = {value} is invalid: {reason}")]
    InvalidParameter {
        /// The metric whose parameter is wrong (`collision`, `support`, `navigability`, ...).
        metric: &'static str,
        /// The parameter's field name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What the value must satisfy.
        reason: &'static str,
    },
    /// A raster would be larger than the raster budget allows (a too fine resolution for a
    /// large floor or opening), found before anything is allocated for it.
    #[error("{metric} raster of {width} x {height} pixels exceeds the limit of {max} pixels per side{}",
        .max_pixels.map(|m| format!(" or {m} pixels in all")).unwrap_or_default())]
    RasterTooLarge {
        /// The metric building the raster (`diagnostics` for the diagnostic images).
        metric: &'static str,
        /// Raster width in pixels.
        width: usize,
        /// Raster height in pixels.
        height: usize,
        /// The most pixels allowed per side.
        max: usize,
        /// The most pixels allowed in all, for a raster that stores a value per pixel (the
        /// opening-clearance occlusion maps and the diagnostic images); `None` for the
        /// navigability raster, which stores runs of pixels.
        max_pixels: Option<usize>,
    },
    /// The evaluation ran past its [`crate::Deadline`] (or was cancelled); the message is
    /// [`sceneeval_scene::DeadlineExceeded`]'s.
    #[error("{}", sceneeval_scene::DeadlineExceeded { stage, budget_seconds: *budget_seconds })]
    DeadlineExceeded {
        /// The metric that was running or about to run.
        stage: &'static str,
        /// The budget in seconds, `None` when the deadline was cancelled without one.
        budget_seconds: Option<f64>,
    },
    /// The free part of an access strip was split into more convex pieces than
    /// [`crate::MAX_STRIP_PIECES`] allows while the footprints over it were subtracted (a
    /// pathological scene: real strips have tens); the metric stops rather than allocating
    /// without bound.
    #[error(
        "accessibility: the free part of the {side} access strip of object {object} splits into {pieces} convex pieces, over the limit of {max}"
    )]
    TooManyPieces {
        /// The object whose strip it is.
        object: sceneeval_scene::ObjectId,
        /// The side of the strip.
        side: sceneeval_geom::Side,
        /// The pieces when the limit was passed.
        pieces: usize,
        /// The limit, [`crate::MAX_STRIP_PIECES`].
        max: usize,
    },
    /// A metric name that is not one of [`crate::Metric::ALL`].
    #[error(
        "unknown metric {name:?}: expected one of collision, support, navigability, accessibility, out_of_bounds, opening_clearance"
    )]
    UnknownMetric {
        /// The name given.
        name: String,
    },
    /// A diagnostic file or folder could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A diagnostic image could not be encoded.
    #[error("cannot encode image {path}: {message}")]
    Image {
        /// The file being written.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
}

/// Checks that `value` is finite and `>= 0` (or `> 0` when `positive`).
pub(crate) fn check_non_negative(
    metric: &'static str,
    name: &'static str,
    value: f64,
    positive: bool,
) -> Result<(), PlausibilityError> {
    let ok = value.is_finite() && if positive { value > 0.0 } else { value >= 0.0 };
    if ok {
        Ok(())
    } else {
        Err(PlausibilityError::InvalidParameter {
            metric,
            name,
            value,
            reason: if positive {
                "must be finite and positive"
            } else {
                "must be finite and non-negative"
            },
        })
    }
}

/// Checks that `value` lies in `[min, max]` (both finite); `reason` states the range for the
/// message, e.g. `"must lie in [0, 1]"`.
pub(crate) fn check_range(
    metric: &'static str,
    name: &'static str,
    value: f64,
    [min, max]: [f64; 2],
    reason: &'static str,
) -> Result<(), PlausibilityError> {
    if (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(PlausibilityError::InvalidParameter {
            metric,
            name,
            value,
            reason,
        })
    }
}

impl From<sceneeval_scene::DeadlineExceeded> for PlausibilityError {
    fn from(e: sceneeval_scene::DeadlineExceeded) -> Self {
        PlausibilityError::DeadlineExceeded {
            stage: e.stage,
            budget_seconds: e.budget_seconds,
        }
    }
}
