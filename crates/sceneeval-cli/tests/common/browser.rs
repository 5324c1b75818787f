//! Headless Chromium for the page tests (`review.rs`, `judge.rs`): the system's browser (found by
//! `sceneeval_test_support::system::chromium`, never a downloaded one), opened on a page with
//! every error the page reports collected.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use headless_chrome::protocol::cdp::types::Event;
use headless_chrome::{Browser, LaunchOptions, Tab};

/// A headless `chromium` with its profile in `profile`, a tab on `url` (waited for, `timeout`
/// for every later wait), and every console error, uncaught exception and browser log error of
/// the page as it comes.
pub fn open(
    chromium: PathBuf,
    url: &str,
    profile: &Path,
    timeout: Duration,
) -> (Browser, Arc<Tab>, Arc<Mutex<Vec<String>>>) {
    let user_data = format!("--user-data-dir={}", profile.display());
    let browser = Browser::new(
        LaunchOptions::default_builder()
            .path(Some(chromium))
            .headless(true)
            .sandbox(false)
            .args(vec![OsStr::new(&user_data), OsStr::new("--no-first-run")])
            .idle_browser_timeout((2 * timeout).max(Duration::from_secs(60)))
            .build()
            .unwrap(),
    )
    .unwrap();
    let tab = browser.new_tab().unwrap();
    tab.set_default_timeout(timeout);
    let errors = Arc::new(Mutex::new(Vec::<String>::new()));
    let sink = Arc::clone(&errors);
    tab.enable_runtime().unwrap();
    tab.enable_log().unwrap();
    tab.add_event_listener(Arc::new(move |event: &Event| {
        let message = match event {
            Event::RuntimeExceptionThrown(e) => Some(format!("exception: {:?}", e.params.exception_details)),
            Event::RuntimeConsoleAPICalled(e)
                if format!("{:?}", e.params.Type).to_lowercase().contains("error") =>
            {
                Some(format!("console: {:?}", e.params.args))
            }
            Event::LogEntryAdded(e)
                if format!("{:?}", e.params.entry.level)
                    .to_lowercase()
                    .contains("error") =>
            {
                Some(format!("log: {}", e.params.entry.text))
            }
            _ => None,
        };
        if let Some(m) = message {
            sink.lock().unwrap().push(m);
        }
    }))
    .unwrap();
    tab.navigate_to(url).unwrap().wait_until_navigated().unwrap();
    (browser, tab, errors)
}
