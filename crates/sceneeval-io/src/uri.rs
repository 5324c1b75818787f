//! Files an asset refers to (glTF buffers and images, OBJ material libraries and textures),
//! resolved **inside the asset's own folder** and nowhere else.
//!
//! An asset file is untrusted input: a glTF buffer URI of `../../etc/passwd`, `%2e%2e/x`,
//! `/abs/path` or `file:///x` must not make the evaluator read a file outside the folder the
//! user pointed it at. The rules, applied by [`resolve_in_folder`] and [`read_uri`]:
//!
//! - `data:[<media type>][;base64],<data>` URIs are decoded in memory (base64, or
//!   percent-encoded text without `;base64`).
//! - Any other URI with a scheme (`file:`, `http:`, `C:` ...) is rejected, as is an absolute
//!   path (`/x`, `\x`) or a path containing a NUL or a backslash.
//! - A relative reference is percent-decoded, split on `/`, and resolved lexically against the
//!   folder of the file that refers to it: `.` components are dropped, `..` removes the
//!   previous component, and a `..` that would leave the folder is rejected.
//! - The resolved path and the folder are then canonicalised (symbolic links followed) and the
//!   file must still lie inside the folder, so a link pointing out of it is rejected too.
//! - A file is read only after its size is checked against the caller's byte limit.
//!
//! Errors name the referring file and the URI (shortened when long), never the contents of any
//! file.

use std::borrow::Cow;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

use base64::Engine;

use crate::IoError;

/// Longest URI quoted in an error message; longer ones (typically `data:` URIs) are cut.
const MAX_QUOTED_URI: usize = 120;

/// A URI shortened for an error message.
pub(crate) fn quoted(uri: &str) -> String {
    if uri.len() <= MAX_QUOTED_URI {
        return uri.to_owned();
    }
    let mut end = MAX_QUOTED_URI;
    while !uri.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}... ({} bytes)", &uri[..end], uri.len())
}

fn rejected(referrer: &Path, uri: &str, reason: impl Into<String>) -> IoError {
    IoError::RejectedUri {
        path: referrer.to_owned(),
        uri: quoted(uri),
        reason: reason.into(),
    }
}

/// Resolves a relative URI reference found in `referrer` to a path inside `folder` (normally
/// `referrer`'s parent folder).
///
/// The path is checked lexically and, when the file exists, again after following symbolic
/// links; a file that does not exist is returned as is (reading it then fails with
/// [`IoError::File`]).
///
/// # Errors
/// [`IoError::RejectedUri`] for a `data:` URI (use [`read_uri`]), a URI with a scheme, an
/// absolute path, a bad percent-encoding, or a path that leaves `folder`.
pub fn resolve_in_folder(folder: &Path, referrer: &Path, uri: &str) -> Result<PathBuf, IoError> {
    if uri.is_empty() {
        return Err(rejected(referrer, uri, "the URI is empty"));
    }
    if has_scheme(uri) {
        return Err(rejected(
            referrer,
            uri,
            "only relative paths inside the asset's folder and data: URIs are allowed",
        ));
    }
    let decoded: Cow<'_, str> = urlencoding::decode(uri)
        .map_err(|_| rejected(referrer, uri, "the percent-encoding is not valid UTF-8"))?;
    if decoded.contains('\0') {
        return Err(rejected(referrer, uri, "the path contains a NUL character"));
    }
    if decoded.contains('\\') {
        return Err(rejected(referrer, uri, "the path contains a backslash"));
    }
    if decoded.starts_with('/') {
        return Err(rejected(referrer, uri, "absolute paths are not allowed"));
    }
    let mut parts: Vec<&str> = Vec::new();
    for part in decoded.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                if parts.pop().is_none() {
                    return Err(rejected(referrer, uri, "the path leaves the asset's folder"));
                }
            }
            _ => parts.push(part),
        }
    }
    if parts.is_empty() {
        return Err(rejected(
            referrer,
            uri,
            "the path names the asset's folder itself",
        ));
    }
    let mut path = folder.to_path_buf();
    for part in &parts {
        // A component such as `C:` is a prefix on Windows; refuse anything that is not a
        // plain name on this platform.
        let mut comps = Path::new(part).components();
        match (comps.next(), comps.next()) {
            (Some(Component::Normal(_)), None) => path.push(part),
            _ => return Err(rejected(referrer, uri, "the path has an unusual component")),
        }
    }
    // Symbolic links: the real file must still be inside the real folder.
    if let (Ok(real_folder), Ok(real_path)) = (folder.canonicalize(), path.canonicalize())
        && !real_path.starts_with(&real_folder)
    {
        return Err(rejected(
            referrer,
            uri,
            "the path leads outside the asset's folder through a symbolic link",
        ));
    }
    Ok(path)
}

/// True when `uri` starts with a URI scheme (`letters:`), which includes Windows drive
/// letters such as `C:`.
fn has_scheme(uri: &str) -> bool {
    let Some(colon) = uri.find(':') else {
        return false;
    };
    let scheme = &uri[..colon];
    !scheme.is_empty()
        && scheme.starts_with(|c: char| c.is_ascii_alphabetic())
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

/// Reads the bytes a URI in `referrer` refers to: a `data:` URI decoded in memory, or a file
/// inside `referrer`'s folder (see the module docs), at most `max_bytes` long.
///
/// # Errors
/// [`IoError::RejectedUri`] as for [`resolve_in_folder`], for a malformed `data:` URI, or for
/// data longer than `max_bytes`; [`IoError::File`] when the file cannot be read.
pub fn read_uri(referrer: &Path, uri: &str, max_bytes: u64) -> Result<Vec<u8>, IoError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let bytes = decode_data_uri(referrer, uri, rest)?;
        if bytes.len() as u64 > max_bytes {
            return Err(rejected(
                referrer,
                uri,
                format!(
                    "the data holds {} bytes, over the limit of {max_bytes}",
                    bytes.len()
                ),
            ));
        }
        return Ok(bytes);
    }
    let folder = referrer.parent().unwrap_or_else(|| Path::new("."));
    let path = resolve_in_folder(folder, referrer, uri)?;
    read_file_limited(&path, max_bytes)
}

/// Reads a whole file after checking that it is a regular file of at most `max_bytes` bytes,
/// so that an oversized file is refused before anything is allocated for it. Every file this
/// crate reads from scene or asset input is read here or opened through `open_input`.
///
/// # Errors
/// [`IoError::File`] when the file cannot be opened or read, or is not a regular file (a
/// named pipe, a directory, a device: refused before it is opened, so nothing blocks);
/// [`IoError::TooLarge`] when it is longer than `max_bytes`.
pub fn read_file_limited(path: &Path, max_bytes: u64) -> Result<Vec<u8>, IoError> {
    let file = open_input(path)?;
    let meta = file.metadata().map_err(|e| IoError::file(path, e))?;
    if meta.len() > max_bytes {
        return Err(IoError::TooLarge {
            path: path.to_owned(),
            what: "file".to_owned(),
            size: meta.len(),
            limit: max_bytes,
        });
    }
    // `take` guards against a file that grows between the check and the read.
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| IoError::file(path, e))?;
    if bytes.len() as u64 > max_bytes {
        return Err(IoError::TooLarge {
            path: path.to_owned(),
            what: "file".to_owned(),
            size: bytes.len() as u64,
            limit: max_bytes,
        });
    }
    Ok(bytes)
}

/// Opens a file of scene or asset input for reading when it is a regular file once symbolic
/// links are followed ([`sceneeval_files::open_regular`]): a named pipe would block the
/// reader forever, so anything else is refused before it is opened.
///
/// # Errors
/// [`IoError::File`] naming the file and saying what it is (`is a named pipe (FIFO), not a
/// regular file`), or the operating system's error.
pub(crate) fn open_input(path: &Path) -> Result<std::fs::File, IoError> {
    sceneeval_files::open_regular(path).map_err(|e| IoError::file(path, e))
}

/// Decodes the part of a `data:` URI after `data:`.
fn decode_data_uri(referrer: &Path, uri: &str, rest: &str) -> Result<Vec<u8>, IoError> {
    let Some((header, payload)) = rest.split_once(',') else {
        return Err(rejected(
            referrer,
            uri,
            "a data: URI needs a comma before its data",
        ));
    };
    if header.split(';').any(|p| p.eq_ignore_ascii_case("base64")) {
        base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| rejected(referrer, uri, format!("bad base64 data: {e}")))
    } else {
        Ok(urlencoding::decode_binary(payload.as_bytes()).into_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder_with_file() -> (tempfile::TempDir, PathBuf) {
        let root = tempfile::tempdir().unwrap();
        let folder = root.path().join("asset");
        std::fs::create_dir_all(folder.join("tex")).unwrap();
        std::fs::write(folder.join("a.bin"), b"inside").unwrap();
        std::fs::write(folder.join("tex/b.png"), b"png").unwrap();
        std::fs::write(root.path().join("secret.txt"), b"TOP SECRET").unwrap();
        let referrer = folder.join("asset.gltf");
        (root, referrer)
    }

    #[test]
    fn relative_paths_inside_the_folder_are_read() {
        let (_root, referrer) = folder_with_file();
        assert_eq!(read_uri(&referrer, "a.bin", 100).unwrap(), b"inside");
        assert_eq!(read_uri(&referrer, "./tex/../a.bin", 100).unwrap(), b"inside");
        assert_eq!(read_uri(&referrer, "tex/b%2Epng", 100).unwrap(), b"png");
    }

    #[test]
    fn escapes_are_rejected_and_never_echo_contents() {
        let (root, referrer) = folder_with_file();
        let secret = root.path().join("secret.txt");
        let absolute = secret.display().to_string();
        let file_url = format!("file://{absolute}");
        for uri in [
            "../secret.txt",
            "%2e%2e/secret.txt",
            "%2E%2E%2Fsecret.txt",
            "tex/../../secret.txt",
            absolute.as_str(),
            file_url.as_str(),
            "http://example.com/x.bin",
            "C:/x.bin",
            "..\\secret.txt",
            "a.bin%00",
            ".",
            "",
        ] {
            let err = read_uri(&referrer, uri, 1000).unwrap_err();
            assert!(matches!(err, IoError::RejectedUri { .. }), "{uri}: {err}");
            let msg = err.to_string();
            assert!(!msg.contains("TOP SECRET"), "{msg}");
            assert!(msg.contains("asset.gltf"), "{msg}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn symbolic_links_out_of_the_folder_are_rejected() {
        let (root, referrer) = folder_with_file();
        let link = referrer.parent().unwrap().join("link.bin");
        std::os::unix::fs::symlink(root.path().join("secret.txt"), &link).unwrap();
        let err = read_uri(&referrer, "link.bin", 1000).unwrap_err();
        assert!(matches!(err, IoError::RejectedUri { .. }), "{err}");
        // A link that stays inside is fine.
        let inner = referrer.parent().unwrap().join("inner.bin");
        std::os::unix::fs::symlink(referrer.parent().unwrap().join("a.bin"), &inner).unwrap();
        assert_eq!(read_uri(&referrer, "inner.bin", 100).unwrap(), b"inside");
    }

    #[test]
    fn data_uris_are_decoded_in_memory() {
        let referrer = Path::new("/nowhere/asset.gltf");
        assert_eq!(
            read_uri(referrer, "data:application/octet-stream;base64,aGVsbG8=", 100).unwrap(),
            b"hello"
        );
        assert_eq!(read_uri(referrer, "data:,a%20b", 100).unwrap(), b"a b");
        assert!(matches!(
            read_uri(referrer, "data:;base64,***", 100),
            Err(IoError::RejectedUri { .. })
        ));
        assert!(matches!(
            read_uri(referrer, "data:nocomma", 100),
            Err(IoError::RejectedUri { .. })
        ));
        assert!(matches!(
            read_uri(referrer, "data:;base64,aGVsbG8=", 4),
            Err(IoError::RejectedUri { .. })
        ));
    }

    #[test]
    fn size_limits_are_checked_before_reading() {
        let (_root, referrer) = folder_with_file();
        let err = read_uri(&referrer, "a.bin", 3).unwrap_err();
        assert!(
            matches!(
                err,
                IoError::TooLarge {
                    size: 6,
                    limit: 3,
                    ..
                }
            ),
            "{err}"
        );
        assert!(matches!(
            read_uri(&referrer, "missing.bin", 100),
            Err(IoError::File { .. })
        ));
    }

    #[test]
    fn long_uris_are_shortened_in_messages() {
        let uri = format!("http://{}", "x".repeat(10_000));
        let err = read_uri(Path::new("/a/b.gltf"), &uri, 10).unwrap_err();
        assert!(err.to_string().len() < 400, "{err}");
    }
}
