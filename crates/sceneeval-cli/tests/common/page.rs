//! A page server started by a test (`sceneeval annotations review`, `sceneeval judge`): the
//! process, its first line of standard output (which names the page's URL) and its port; the
//! page's token; Ctrl-C; and waiting for a page or a file to change.

use std::io::{BufRead, BufReader, Read};
use std::process::{Child, ChildStdout, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// A running page server, killed when dropped.
pub struct PageProcess {
    /// The process.
    pub child: Child,
    /// The rest of its standard output.
    pub stdout: BufReader<ChildStdout>,
    /// Its first line of standard output, which names the URL.
    pub first_line: String,
    /// The port of the URL.
    pub port: u16,
}

impl Drop for PageProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl PageProcess {
    /// Starts `command` (standard output piped, standard error dropped) and reads the port
    /// from the `http://127.0.0.1:PORT/` its first line names.
    pub fn spawn(mut command: Command) -> PageProcess {
        let mut child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut first_line = String::new();
        stdout.read_line(&mut first_line).unwrap();
        let url = first_line
            .split_whitespace()
            .find(|w| w.starts_with("http://127.0.0.1:"))
            .unwrap_or_else(|| panic!("no URL in {first_line:?}"));
        let port = url
            .trim_start_matches("http://127.0.0.1:")
            .trim_end_matches('/')
            .parse()
            .unwrap();
        PageProcess {
            child,
            stdout,
            first_line,
            port,
        }
    }

    /// `127.0.0.1:PORT`, the `Host` the server accepts.
    pub fn host(&self) -> String {
        format!("127.0.0.1:{}", self.port)
    }

    /// The page's URL.
    pub fn url(&self) -> String {
        format!("http://127.0.0.1:{}/", self.port)
    }

    /// Sends SIGINT (Ctrl-C) to the server.
    pub fn send_interrupt(&self) {
        let pid = self.child.id().to_string();
        assert!(
            Command::new("kill")
                .args(["-INT", &pid])
                .status()
                .unwrap()
                .success()
        );
    }

    /// Sends SIGINT (Ctrl-C) and returns how the process ended and the rest of its standard
    /// output.
    pub fn interrupt(mut self) -> (ExitStatus, String) {
        self.send_interrupt();
        let mut rest = String::new();
        self.stdout.read_to_string(&mut rest).unwrap();
        (self.child.wait().unwrap(), rest)
    }
}

/// The per-run token a served page carries in its `sceneeval-token` meta tag.
pub fn token_in(page: &str) -> String {
    let slot = "name=\"sceneeval-token\" content=\"";
    let start = page.find(slot).unwrap() + slot.len();
    page[start..start + 32].to_owned()
}

/// Waits until `check` holds, for at most `limit`.
pub fn wait_for(what: &str, limit: Duration, mut check: impl FnMut() -> bool) {
    let start = Instant::now();
    while !check() {
        assert!(start.elapsed() < limit, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(50));
    }
}
