//! An error with its causes, as every front end shows it: [`ErrorChain`] prints an error and
//! each cause it does not already say, on one line (`{}`: `message: cause: cause`) or one
//! cause per line (`{:#}`: `message` then `  caused by: cause`). The CLI, the Python package,
//! `relate`'s answers and the per-scene records all print chains through it.

use std::error::Error;
use std::fmt;

/// The causes of `error` (its `source()`, their sources, ...), outermost first.
pub fn causes<'a>(error: &'a (dyn Error + 'static)) -> impl Iterator<Item = &'a (dyn Error + 'static)> {
    std::iter::successors(error.source(), |e: &&'a (dyn Error + 'static)| {
        let e: &'a (dyn Error + 'static) = *e;
        e.source()
    })
}

/// An error message and its causes, printed as the front ends print them; see the module docs.
/// A cause whose text the message before it already contains (an error that writes its
/// source into its own message) is printed once.
///
/// ```
/// use sceneeval_files::ErrorChain;
///
/// #[derive(Debug)]
/// struct NotWritable(std::io::Error);
/// impl std::fmt::Display for NotWritable {
///     fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
///         f.write_str("output folder out is not writable")
///     }
/// }
/// impl std::error::Error for NotWritable {
///     fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
///         Some(&self.0)
///     }
/// }
///
/// let err = NotWritable(std::io::Error::other("disk full"));
/// assert_eq!(ErrorChain::new(&err).to_string(), "output folder out is not writable: disk full");
/// assert_eq!(
///     format!("{:#}", ErrorChain::new(&err)),
///     "output folder out is not writable\n  caused by: disk full"
/// );
/// // A record keeps the causes as text: they print the same way.
/// let chain = ErrorChain::from_parts("scene_3 failed", ["asset missing", "no such file"]);
/// assert_eq!(format!("{chain:#}"), "scene_3 failed\n  caused by: asset missing\n  caused by: no such file");
/// ```
#[derive(Debug, Clone)]
pub struct ErrorChain {
    message: String,
    causes: Vec<String>,
}

impl ErrorChain {
    /// The chain of `error`.
    pub fn new(error: &(dyn Error + 'static)) -> Self {
        ErrorChain::from_parts(error.to_string(), causes(error).map(|c| c.to_string()))
    }

    /// A chain from a message and its causes' messages (as a record keeps them).
    pub fn from_parts<S: Into<String>>(
        message: impl Into<String>,
        causes: impl IntoIterator<Item = S>,
    ) -> Self {
        ErrorChain {
            message: message.into(),
            causes: causes.into_iter().map(Into::into).collect(),
        }
    }
}

impl fmt::Display for ErrorChain {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)?;
        let mut said = self.message.clone();
        for cause in &self.causes {
            if said.contains(cause.as_str()) {
                continue;
            }
            if f.alternate() {
                write!(f, "\n  caused by: {cause}")?;
            } else {
                write!(f, ": {cause}")?;
            }
            said.push_str(cause);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An error that writes its source into its own message.
    #[derive(Debug)]
    struct Repeats(&'static str, std::io::Error);

    impl fmt::Display for Repeats {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "reading {}: {}", self.0, self.1)
        }
    }

    impl Error for Repeats {
        fn source(&self) -> Option<&(dyn Error + 'static)> {
            Some(&self.1)
        }
    }

    #[test]
    fn causes_already_said_are_printed_once() {
        let err = Repeats("scene_1.json", std::io::Error::other("no such file"));
        assert_eq!(causes(&err).count(), 1);
        assert_eq!(
            ErrorChain::new(&err).to_string(),
            "reading scene_1.json: no such file"
        );
        assert_eq!(
            format!("{:#}", ErrorChain::new(&err)),
            "reading scene_1.json: no such file"
        );
    }
}
