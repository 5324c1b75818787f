//! A log writer that tests read back: what a `tracing` subscriber wrote, as text.
//!
//! ```
//! use std::io::Write;
//! use sceneeval_test_support::logs::SharedBuffer;
//!
//! let buffer = SharedBuffer::default();
//! // A subscriber takes a writer maker such as `move || writer.clone()`.
//! let mut writer = buffer.clone();
//! writer.write_all(b"WARN one\n").unwrap();
//! assert_eq!(buffer.text(), "WARN one\n");
//! ```

use std::io::Write;
use std::sync::{Arc, Mutex, PoisonError};

/// Bytes written through any of its clones, read back with [`SharedBuffer::text`].
#[derive(Debug, Clone, Default)]
pub struct SharedBuffer(Arc<Mutex<Vec<u8>>>);

impl SharedBuffer {
    /// Everything written so far (invalid UTF-8 replaced).
    pub fn text(&self) -> String {
        let bytes = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        String::from_utf8_lossy(&bytes).into_owned()
    }
}

impl Write for SharedBuffer {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}
