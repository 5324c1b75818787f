//! Tests that need a system package: they run when it is installed, are skipped with the reason
//! and the package to install when it is not, and fail when the environment requires it.
//!
//! Two packages are needed: the GPU driver of the renderer ([`GPU`]) and the browser the
//! report's pages are checked in ([`BROWSER`]).
//!
//! A fresh machine without a GPU driver still passes `cargo test --workspace` (every test that
//! renders says once per test binary that it skipped and why), while CI, which installs the
//! driver, sets [`GPU.require_var`](Requirement::require_var) (`SCENEEVAL_REQUIRE_GPU=1` in
//! `.ci/run`) so that a missing driver fails the run instead of hiding every render test.
//!
//! The one decision is [`decide`] (pure, tested with the variable set and unset and the driver
//! present and absent); [`available`] applies it to a probe's result. Every test that needs a
//! renderer starts with it:
//!
//! ```
//! use sceneeval_test_support::system::{GPU, available};
//!
//! // In a render test the probe is `Renderer::new()` and the test for a missing driver
//! // `RenderError::is_missing_driver`; here a probe that finds the package.
//! let probe: Result<u32, String> = Ok(7);
//! let Some(renderer) = available(&GPU, probe, |_| true) else {
//!     return; // skipped: the reason was printed once
//! };
//! assert_eq!(renderer, 7);
//! ```

use std::fmt::Display;
use std::io::Write;
use std::sync::Mutex;

/// A system package some tests need.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Requirement {
    /// What it is, for messages (`a Vulkan driver`).
    pub what: &'static str,
    /// What to install (`mesa-vulkan-drivers libvulkan1`, Debian/Ubuntu package names).
    pub install: &'static str,
    /// The environment variable that, set to anything but empty or `0`, makes a missing
    /// package a failure.
    pub require_var: &'static str,
}

/// The GPU driver the renderer needs: Vulkan, on a GPU or Mesa's software driver (lavapipe).
pub const GPU: Requirement = Requirement {
    what: "a Vulkan driver (a GPU's, or Mesa's software driver lavapipe)",
    install: "mesa-vulkan-drivers libvulkan1",
    require_var: "SCENEEVAL_REQUIRE_GPU",
};

/// The web browser the report's tests load pages in: Debian's `chromium`, run headless.
pub const BROWSER: Requirement = Requirement {
    what: "a headless web browser (chromium)",
    install: "chromium",
    require_var: "SCENEEVAL_REQUIRE_BROWSER",
};

/// The system's chromium (`/usr/bin/chromium` or `/usr/bin/chromium-browser`), never a
/// downloaded one, when installed; else [`available`] decides (skip, or fail when
/// `SCENEEVAL_REQUIRE_BROWSER` is set).
pub fn chromium() -> Option<std::path::PathBuf> {
    let probe = ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .iter()
        .map(std::path::PathBuf::from)
        .find(|p| p.exists())
        .ok_or_else(|| "no /usr/bin/chromium".to_owned());
    available(&BROWSER, probe, |_| true)
}

/// What to do with a test that needs a package.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Decision {
    /// The package is there: run the test.
    Run,
    /// It is missing and not required: pass without running, after saying this.
    Skip(String),
    /// It is missing and required: fail with this.
    Fail(String),
}

/// Whether `value` (the requirement variable's value, `None` when unset) requires the package:
/// set to anything but empty or `0`.
pub fn is_required(value: Option<&str>) -> bool {
    value.is_some_and(|v| !v.trim().is_empty() && v.trim() != "0")
}

/// The decision for a test needing `req`: `missing` is why the package was not found (`None`
/// when it was), `required` whether the environment requires it ([`is_required`]).
pub fn decide(req: &Requirement, missing: Option<&str>, required: bool) -> Decision {
    match (missing, required) {
        (None, _) => Decision::Run,
        (Some(why), false) => Decision::Skip(format!(
            "skipped: these tests need {} and found none ({why}). Install it (Debian/Ubuntu: \
             apt-get install {}) to run them; set {}=1 to make this a failure.",
            req.what, req.install, req.require_var
        )),
        (Some(why), true) => Decision::Fail(format!(
            "{} is set, but no {} was found ({why}). Install {}.",
            req.require_var, req.what, req.install
        )),
    }
}

/// The requirements already reported as skipped by this test binary.
static REPORTED: Mutex<Vec<&'static str>> = Mutex::new(Vec::new());

/// Applies [`decide`] to `probe`, the result of making what the test needs (a renderer):
/// `Some(value)` to run the test with; `None` when the package is missing (`is_missing` says
/// which errors mean that) and not required, after printing the reason once per test binary
/// (to the process's standard error, past the test harness's capture, so that it shows in a
/// passing run).
///
/// # Panics
/// When the package is missing and required ([`Requirement::require_var`] set), and on any
/// other error of the probe: those are failures, not a missing package.
pub fn available<T, E: Display>(
    req: &Requirement,
    probe: Result<T, E>,
    is_missing: impl Fn(&E) -> bool,
) -> Option<T> {
    let required = is_required(std::env::var(req.require_var).ok().as_deref());
    apply(req, probe, is_missing, required, |message| {
        report_once(req, message, &mut std::io::stderr());
    })
}

/// [`available`] with the requirement's state given and the skip message passed to `report`.
#[allow(clippy::panic)] // Failing the test is the point: this runs only inside tests.
fn apply<T, E: Display>(
    req: &Requirement,
    probe: Result<T, E>,
    is_missing: impl Fn(&E) -> bool,
    required: bool,
    report: impl FnOnce(&str),
) -> Option<T> {
    let error = match probe {
        Ok(value) => return Some(value),
        Err(e) => e,
    };
    assert!(is_missing(&error), "{error}");
    match decide(req, Some(&error.to_string()), required) {
        Decision::Run => None,
        Decision::Skip(message) => {
            report(&message);
            None
        }
        Decision::Fail(message) => panic!("{message}"),
    }
}

/// Writes `message` to `out` the first time `req` is skipped in this process.
fn report_once(req: &Requirement, message: &str, out: &mut dyn Write) {
    let mut reported = REPORTED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if !reported.contains(&req.require_var) {
        reported.push(req.require_var);
        let _ = writeln!(out, "note: {message}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_variable_requires_the_package_unless_empty_or_zero() {
        assert!(!is_required(None));
        assert!(!is_required(Some("")));
        assert!(!is_required(Some("0")));
        assert!(!is_required(Some(" 0 ")));
        assert!(is_required(Some("1")));
        assert!(is_required(Some("yes")));
    }

    #[test]
    fn present_runs_missing_skips_with_the_package_or_fails_when_required() {
        // Driver present: run, whatever the variable.
        assert_eq!(decide(&GPU, None, false), Decision::Run);
        assert_eq!(decide(&GPU, None, true), Decision::Run);
        // Driver absent, not required: skipped, saying what to install and how to require it.
        let Decision::Skip(skip) = decide(&GPU, Some("no adapter"), false) else {
            panic!("not a skip")
        };
        assert!(
            skip.contains("apt-get install mesa-vulkan-drivers libvulkan1"),
            "{skip}"
        );
        assert!(
            skip.contains("(no adapter)") && skip.contains("SCENEEVAL_REQUIRE_GPU=1"),
            "{skip}"
        );
        // Driver absent, required (CI): a failure naming the variable and the package.
        let Decision::Fail(fail) = decide(&GPU, Some("no adapter"), true) else {
            panic!("not a failure")
        };
        assert!(fail.starts_with("SCENEEVAL_REQUIRE_GPU is set"), "{fail}");
        assert!(fail.contains("mesa-vulkan-drivers libvulkan1"), "{fail}");
        // The browser: the same decision, its own package and variable.
        let Decision::Skip(skip) = decide(&BROWSER, Some("chromium: not found"), false) else {
            panic!("not a skip")
        };
        assert!(
            skip.contains("apt-get install chromium") && skip.contains("SCENEEVAL_REQUIRE_BROWSER=1"),
            "{skip}"
        );
        assert!(
            matches!(decide(&BROWSER, Some("x"), true), Decision::Fail(f) if f.starts_with("SCENEEVAL_REQUIRE_BROWSER is set"))
        );
    }

    /// A requirement of its own, so that the process's environment decides nothing here.
    const FAKE: Requirement = Requirement {
        what: "a fake package",
        install: "fake-package",
        require_var: "SCENEEVAL_TEST_SUPPORT_REQUIRE_FAKE_NEVER_SET",
    };

    #[test]
    fn a_probe_gives_its_value_skips_with_the_reason_or_fails_when_required() {
        let mut said = Vec::new();
        assert_eq!(
            apply(
                &FAKE,
                Ok::<_, String>(3),
                |_| true,
                true,
                |m| said.push(m.to_owned())
            ),
            Some(3)
        );
        let missing = || Err::<u8, _>("not installed".to_owned());
        assert_eq!(
            apply(&FAKE, missing(), |_| true, false, |m| said.push(m.to_owned())),
            None
        );
        assert_eq!(said.len(), 1);
        assert!(said[0].contains("(not installed)") && said[0].contains("apt-get install fake-package"));
        let failed = std::panic::catch_unwind(|| apply(&FAKE, missing(), |_| true, true, |_| {}));
        assert!(failed.is_err(), "required and missing: the test fails");
        let other = std::panic::catch_unwind(|| apply(&FAKE, missing(), |_| false, false, |_| {}));
        assert!(
            other.is_err(),
            "an error that is not a missing package fails the test"
        );
        // Without the variable set, the process-level entry point skips too.
        assert_eq!(available(&FAKE, Ok::<_, String>(5), |_| true), Some(5));
    }

    #[test]
    fn the_reason_is_reported_once_per_test_binary() {
        let mut out = Vec::new();
        for _ in 0..3 {
            report_once(&FAKE, "skipped: fake", &mut out);
        }
        assert_eq!(String::from_utf8(out).unwrap(), "note: skipped: fake\n");
    }
}
