//! The fast path of reading a line (`answer::parse_line`): a query by name,
//! `{"id":17,"relation":"near","target":"bed","room":"bedroom"}`, is a flat JSON object whose
//! values are strings without escapes and perhaps an integer. Reading such a line with
//! serde_json's derived visitors costs about 2,300 instructions, more than the line's own
//! work and many times a cheap predicate; this scanner reads it in a few hundred.
//!
//! It accepts a strict subset of what serde_json accepts and returns `None` for everything
//! else (a nested object or array, an escape, a control character, a number that is not a
//! plain integer, `true`/`false`/`null`, an unknown or repeated key, a declaration's
//! `object`, a trailing character, a byte-order mark...), which serde_json then reads and, if
//! it must, refuses with its own message. Where it accepts, it gives the [`Line`] serde_json
//! gives: the property test below checks both on lines built from every token it handles and
//! many it does not.

use std::borrow::Cow;

use crate::{Operand, RoomOperand};

use crate::line::{Line, RawText, Text};

/// Reads the line in `text` into `line` (empty, as [`Line::default`]) if it is a flat object
/// this scanner reads (see the module docs); `None` otherwise, with `line` partly filled (the
/// caller starts again from an empty line).
#[inline]
pub(crate) fn read<'a>(text: &'a str, line: &mut Line<'a>) -> Option<()> {
    let bytes = text.as_bytes();
    let mut at = skip_whitespace(bytes, 0);
    if bytes.get(at) != Some(&b'{') {
        return None;
    }
    // A nested object or array (an object or a room written in place, `targets`) goes to
    // serde_json at once: one vector search instead of scanning the keys before it.
    if memchr::memchr2(b'{', b'[', &bytes[at + 1..]).is_some() {
        return None;
    }
    at = skip_whitespace(bytes, at + 1);
    if bytes.get(at) == Some(&b'}') {
        at += 1;
    } else {
        loop {
            let (key, next) = key(bytes, at)?;
            at = skip_whitespace(bytes, next);
            if bytes.get(at) != Some(&b':') {
                return None;
            }
            at = skip_whitespace(bytes, at + 1);
            at = match key {
                ID => set(&mut line.id, scalar(text, at)?)?,
                VERSION => set(&mut line.version, scalar(text, at)?)?,
                RELATION => set(&mut line.relation, text_value(text, at)?)?,
                SIDE => set(&mut line.side, text_value(text, at)?)?,
                ARCH => set(&mut line.arch, text_value(text, at)?)?,
                DECLARE => set(&mut line.declare, text_value(text, at)?)?,
                TARGET => set(&mut line.target, name(text, at, Operand::Name)?)?,
                ANCHOR => set(&mut line.anchor, name(text, at, Operand::Name)?)?,
                ROOM => set(&mut line.room, name(text, at, RoomOperand::Name)?)?,
                _ => return None,
            };
            at = skip_whitespace(bytes, at);
            match bytes.get(at) {
                Some(b',') => at = skip_whitespace(bytes, at + 1),
                Some(b'}') => {
                    at += 1;
                    break;
                }
                _ => return None,
            }
        }
    }
    (skip_whitespace(bytes, at) == bytes.len()).then_some(())
}

/// A key of at most eight bytes packed into one little-endian word, so that a key is told
/// from the others in one comparison. (No key has a NUL byte: control characters leave the
/// line to serde_json.)
const fn word(key: &str) -> u64 {
    let key = key.as_bytes();
    let mut word = 0;
    let mut i = 0;
    while i < key.len() {
        word |= (key[i] as u64) << (8 * i);
        i += 1;
    }
    word
}

const ID: u64 = word("id");
const VERSION: u64 = word("version");
const RELATION: u64 = word("relation");
const SIDE: u64 = word("side");
const ARCH: u64 = word("arch");
const DECLARE: u64 = word("declare");
const TARGET: u64 = word("target");
const ANCHOR: u64 = word("anchor");
const ROOM: u64 = word("room");

/// The key that starts at `at`, as its [`word`], and the index after its closing quote; `None`
/// for a key longer than eight bytes (none of the scanner's) or with an escape or a control
/// character (`"id\u{0}"` would otherwise pack to the word of `"id"`).
#[inline(always)]
fn key(bytes: &[u8], at: usize) -> Option<(u64, usize)> {
    if bytes.get(at) != Some(&b'"') {
        return None;
    }
    let start = at + 1;
    // The eight bytes after the opening quote as one word, when the line has them (it does
    // but for the last key of a very short line).
    let Some(chunk) = bytes.get(start..start + 8) else {
        let end = string_stop(bytes, start)?;
        if bytes[end] != b'"' {
            return None;
        }
        let mut word = [0; 8];
        word[..end - start].copy_from_slice(&bytes[start..end]);
        return Some((u64::from_le_bytes(word), end + 1));
    };
    let word = u64::from_le_bytes(chunk.try_into().ok()?);
    let stops = stop_bytes(word);
    if stops == 0 {
        // Eight plain bytes: an eight-byte key if a quote follows.
        return (bytes.get(start + 8) == Some(&b'"')).then_some((word, start + 9));
    }
    let length = stops.trailing_zeros() / 8;
    if chunk[length as usize] != b'"' {
        return None;
    }
    let word = if length == 0 {
        0
    } else {
        word & (u64::MAX >> (64 - 8 * length))
    };
    Some((word, start + length as usize + 1))
}

/// `byte` in each of a word's eight bytes.
const fn splat(byte: u8) -> u64 {
    u64::from_le_bytes([byte; 8])
}

/// The high bit of each byte of `word` that is zero. Exact for the lowest such byte (the
/// first in the line: words are read little-endian); above it a bit may be set spuriously by
/// the borrow, so only the lowest set bit is ever read.
const fn zero_bytes(word: u64) -> u64 {
    word.wrapping_sub(splat(1)) & !word & splat(0x80)
}

/// The high bit of each byte of `word` below 0x20 (a control character), exact for the lowest
/// such byte as in [`zero_bytes`].
const fn control_bytes(word: u64) -> u64 {
    word.wrapping_sub(splat(0x20)) & !word & splat(0x80)
}

/// The high bit of each byte of `word` that is a quote, a backslash or a control character,
/// exact for the lowest such byte (see [`zero_bytes`]: the lowest bit set in any of the three
/// masks is a true one).
#[inline(always)]
const fn stop_bytes(word: u64) -> u64 {
    zero_bytes(word ^ splat(b'"')) | zero_bytes(word ^ splat(b'\\')) | control_bytes(word)
}

/// The index of the first quote, backslash or control character at or after `at` (in words of
/// eight bytes, then one byte at a time), or `None` at the end of the line.
#[inline(always)]
fn string_stop(bytes: &[u8], mut at: usize) -> Option<usize> {
    while let Some(chunk) = bytes.get(at..at + 8) {
        let word = u64::from_le_bytes(chunk.try_into().ok()?);
        let stops = stop_bytes(word);
        if stops != 0 {
            return Some(at + (stops.trailing_zeros() / 8) as usize);
        }
        at += 8;
    }
    let length = bytes
        .get(at..)?
        .iter()
        .position(|&b| STRING_STOPS[usize::from(b)])?;
    Some(at + length)
}

/// Stores `value` in an empty `slot` and returns where the value ended; `None` if the key
/// came before (serde_json refuses a repeated field).
#[inline(always)]
fn set<T>(slot: &mut Option<T>, (value, end): (T, usize)) -> Option<usize> {
    if slot.is_some() {
        return None;
    }
    *slot = Some(value);
    Some(end)
}

/// The first byte at or after `at` that is not JSON whitespace (space, tab, line feed,
/// carriage return; not form feed, which JSON does not allow).
fn skip_whitespace(bytes: &[u8], mut at: usize) -> usize {
    while let Some(b' ' | b'\t' | b'\n' | b'\r') = bytes.get(at) {
        at += 1;
    }
    at
}

/// The bytes that end the scan of a string: the closing quote, and the backslash and control
/// characters, which leave the line to serde_json (one table lookup per byte).
const STRING_STOPS: [bool; 256] = {
    let mut stops = [false; 256];
    let mut byte = 0;
    while byte < 0x20 {
        stops[byte] = true;
        byte += 1;
    }
    stops[b'"' as usize] = true;
    stops[b'\\' as usize] = true;
    stops
};

/// The content of the string that starts at `at` and the index after its closing quote, if it
/// has neither an escape nor a control character.
#[inline(always)]
fn string(text: &str, at: usize) -> Option<(&str, usize)> {
    let bytes = text.as_bytes();
    if bytes.get(at) != Some(&b'"') {
        return None;
    }
    let start = at + 1;
    let end = string_stop(bytes, start)?;
    // `end` is an ASCII quote (or the scan stopped at a byte that refuses the line), so both
    // ends are character boundaries.
    (bytes[end] == b'"').then(|| (&text[start..end], end + 1))
}

/// A string value as [`Text`].
#[inline(always)]
fn text_value(text: &str, at: usize) -> Option<(Text<'_>, usize)> {
    string(text, at).map(|(s, end)| (Text(Cow::Borrowed(s)), end))
}

/// A string value as a name operand built by `make`.
#[inline(always)]
fn name<'a, T>(text: &'a str, at: usize, make: fn(Cow<'a, str>) -> T) -> Option<(T, usize)> {
    string(text, at).map(|(s, end)| (make(Cow::Borrowed(s)), end))
}

/// An id or a version: a string without escapes (quotes included) or an integer, as written.
#[inline(always)]
fn scalar(text: &str, at: usize) -> Option<(RawText<'_>, usize)> {
    let bytes = text.as_bytes();
    let end = match bytes.get(at)? {
        b'"' => string(text, at)?.1,
        _ => {
            let digits = at + usize::from(bytes[at] == b'-');
            let count = bytes
                .get(digits..)?
                .iter()
                .take_while(|b| b.is_ascii_digit())
                .count();
            // JSON refuses leading zeros; a fraction or an exponent goes to serde_json, as
            // does anything glued to the digits (`12a`), since the caller then finds no `,`
            // or `}`.
            if count == 0 || (count > 1 && bytes[digits] == b'0') {
                return None;
            }
            digits + count
        }
    };
    Some((RawText(&text[at..end]), end))
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;
    use proptest::strategy::ValueTree;

    use super::*;

    /// The line in `text`, if the scanner reads it.
    fn parse(text: &str) -> Option<Line<'_>> {
        let mut line = Line::default();
        read(text, &mut line).map(|()| line)
    }

    /// Both readings of `text`, as text (a [`Line`] is not `PartialEq`: its inline objects
    /// are not).
    fn both(text: &str) -> (Option<String>, Result<String, String>) {
        (
            parse(text).map(|l| format!("{l:?}")),
            serde_json::from_str::<Line<'_>>(text)
                .map(|l| format!("{l:?}"))
                .map_err(|e| e.to_string()),
        )
    }

    #[test]
    fn reads_queries_and_declarations_by_name() {
        let line = parse(r#"{"id":17,"relation":"near","target":"bed","room":"bedroom"}"#).unwrap();
        assert_eq!(line.id, Some(RawText("17")));
        assert!(matches!(&line.relation, Some(Text(r)) if r == "near"));
        assert!(matches!(&line.target, Some(Operand::Name(n)) if n == "bed"));
        assert!(matches!(&line.room, Some(RoomOperand::Name(n)) if n == "bedroom"));
        assert!(line.anchor.is_none() && line.version.is_none() && line.side.is_none());
        let line = parse(
            " {\t\"version\" : 1 ,\r\n \"id\":\"q-7\", \"relation\":\"next_to\",\"arch\":\"wall\",\"side\":\"left\",\"anchor\":\"café\",\"declare\":\"\"}\n",
        )
        .unwrap();
        assert_eq!(line.version, Some(RawText("1")));
        assert_eq!(line.id, Some(RawText("\"q-7\"")));
        assert!(matches!(&line.anchor, Some(Operand::Name(n)) if n == "café"));
        assert!(matches!(&line.declare, Some(Text(d)) if d.is_empty()));
        assert!(parse("{}").is_some());
        assert_eq!(parse(r#"{"id":-0}"#).unwrap().id, Some(RawText("-0")));
        // Every line the benchmark generator writes for queries by name takes this path.
        for text in [
            r#"{"id":0,"relation":"hang_from_ceiling","target":"bed","room":"bedroom"}"#,
            r#"{"id":99999,"relation":"across_from","target":"bed","arch":"window","room":"bedroom"}"#,
        ] {
            assert!(parse(text).is_some(), "{text}");
        }
    }

    #[test]
    fn words_find_the_first_stop_as_bytes_do() {
        // Every length up to three words, a stop of each kind at every place, with bytes
        // around it that a wrong mask would take for one (0x20, 0x21, 0x23, 0x5b, 0x5d, 0x7f,
        // UTF-8 bytes).
        let fillers = [b'a', b' ', b'!', b'#', b'[', b']', 0x7f, 0xc3, 0xa9, 0xff];
        for length in 0..24 {
            for filler in fillers {
                for stop_at in 0..=length {
                    for stop in [b'"', b'\\', 0x00, 0x1f, 0x0a] {
                        let mut bytes = vec![filler; length];
                        if stop_at < length {
                            bytes[stop_at] = stop;
                        }
                        for start in 0..length.min(9) {
                            let naive = bytes[start..]
                                .iter()
                                .position(|&b| b == b'"' || b == b'\\' || b < 0x20)
                                .map(|p| p + start);
                            assert_eq!(string_stop(&bytes, start), naive, "{bytes:?} from {start}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn keys_are_read_in_one_word_or_byte_by_byte() {
        for (text, key_word) in [
            (r#""id":1,"relation":"near"}"#, Some((ID, 4))),
            (r#""id":1}"#, Some((ID, 4))),
            (r#""relation":"near"}"#, Some((RELATION, 10))),
            (r#""relation""#, Some((RELATION, 10))),
            (r#""room":"bedroom"}"#, Some((ROOM, 6))),
            (r#""":1,"relation":"near"}"#, Some((0, 2))),
            (r#""":1}"#, Some((0, 2))),
            (r#""relations":"near"}"#, None),
            (r#""relations""#, None),
            (r#""id"#, None),
        ] {
            assert_eq!(key(text.as_bytes(), 0), key_word, "{text}");
        }
        // A key with an escape or a control character is not read, even where it would pack
        // to one of the scanner's words.
        for text in [
            r#""i\d":1,"relation":"near"}"#,
            "\"i\td\":1,\"relation\":1}",
            r#""i\"":1}"#,
            "\"id\u{0}\":1,\"relation\":\"near\"}",
            "\"id\u{0}\":1}",
            "\"target\u{1f}\":\"bed\",\"room\":\"r\"}",
        ] {
            assert_eq!(key(text.as_bytes(), 0), None, "{text:?}");
        }
    }

    #[test]
    fn leaves_everything_else_to_serde_json() {
        for text in [
            "",
            "[]",
            "{",
            r#"{"id":1"#,
            r#"{"id":1,}"#,
            r#"{,"id":1}"#,
            r#"{"id":1}x"#,
            r#"{"id":1} {}"#,
            "\u{feff}{}",
            "{}\u{c}",
            r#"{"id":1.5}"#,
            r#"{"id":1e3}"#,
            r#"{"id":01}"#,
            r#"{"id":-}"#,
            r#"{"id":12a}"#,
            r#"{"id":null}"#,
            r#"{"id":true}"#,
            r#"{"id":[1]}"#,
            r#"{"id":"a\"b"}"#,
            r#"{"relation":"n\u0065ar"}"#,
            "{\"relation\":\"a\tb\"}",
            r#"{"relation":1}"#,
            r#"{"target":{"center":[0,0,0],"half_size":[1,1,1]}}"#,
            r#"{"room":{"floor":[]}}"#,
            r#"{"declare":"bed","object":"other"}"#,
            r#"{"targets":["a","b"]}"#,
            r#"{"relation":"near","relation":"far"}"#,
            r#"{"id":1,"id":2}"#,
            r#"{"bogus":"x"}"#,
            r#"{"Id":1}"#,
            r#"{"id" 1}"#,
        ] {
            assert!(parse(text).is_none(), "{text:?}");
        }
    }

    /// A token of a generated line: the pieces the scanner reads and pieces it must refuse.
    fn token() -> impl Strategy<Value = String> {
        prop_oneof![
            Just("{".to_owned()),
            Just("}".to_owned()),
            Just(",".to_owned()),
            Just(":".to_owned()),
            Just("[".to_owned()),
            Just("]".to_owned()),
            prop::sample::select(vec![
                "\"id\"",
                "\"version\"",
                "\"relation\"",
                "\"side\"",
                "\"arch\"",
                "\"declare\"",
                "\"target\"",
                "\"anchor\"",
                "\"room\"",
                "\"object\"",
                "\"targets\"",
                "\"idx\"",
                "\"\"",
            ])
            .prop_map(str::to_owned),
            "\"[a-z_é ]{0,20}\"",
            "\"[a-z]{0,11}\\\\[\"\\\\/bnrtu]{1}[0-9a-f]{0,4}\"",
            "\"[a-z]{0,10}[\\x00-\\x1f][a-z]{0,3}\"",
            "-?[0-9]{1,25}",
            "-?[0-9]{1,3}\\.[0-9]{1,3}",
            "[0-9]e[+-]?[0-9]{1,3}",
            prop::sample::select(vec!["true", "false", "null", "-", "nul", "tru"]).prop_map(str::to_owned),
            prop::sample::select(vec![" ", "\t", "\n", "\r", "\u{c}", "\u{feff}", "x"])
                .prop_map(str::to_owned),
        ]
    }

    /// Well-formed flat lines with plain values (most of which the scanner takes) ...
    fn flat_line() -> impl Strategy<Value = String> {
        let key = prop::sample::select(vec![
            "id",
            "version",
            "relation",
            "side",
            "arch",
            "declare",
            "target",
            "anchor",
            "room",
            "object",
            "bogus",
            "id\u{0}",
            "room\u{1f}",
            r"i\u0064",
            "relation\u{0}",
        ]);
        let value = prop_oneof![
            12 => "\"[a-z_é]{0,20}\"",
            3 => "-?(0|[1-9][0-9]{0,20})",
            1 => "\"a\\\\u0062\"",
            1 => "1\\.5",
            1 => "-?0[0-9]{1,3}",
            1 => "\"[a-z]{0,2}[\\x00-\\x1f]\"",
            1 => Just("null".to_owned()),
            1 => Just("{}".to_owned()),
        ];
        let space = prop::sample::select(vec!["", "", " ", "\t", "\r\n"]);
        prop::collection::vec((space.clone(), key, space.clone(), value, space.clone()), 0..6).prop_map(
            |fields| {
                let fields: Vec<String> = fields
                    .into_iter()
                    .map(|(a, k, b, v, c)| format!("{a}\"{k}\"{b}:{c}{v}{a}"))
                    .collect();
                format!("{{{}}}\n", fields.join(","))
            },
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4000))]

        /// ... and arbitrary sequences of tokens: wherever the scanner reads a line, serde_json
        /// reads it too, to the same fields.
        #[test]
        fn agrees_with_serde_json(text in prop_oneof![
            flat_line(),
            prop::collection::vec(token(), 0..14).prop_map(|t| t.concat()),
            prop::collection::vec(token(), 0..10).prop_map(|t| format!("{{{}}}", t.concat())),
        ]) {
            let (fast, slow) = both(&text);
            if let Some(fast) = fast {
                prop_assert_eq!(Ok(fast), slow, "{:?}", text);
            }
        }
    }

    #[test]
    fn the_generated_lines_exercise_the_fast_path() {
        // Guards the property test against vacuity: most well-formed flat lines with plain
        // values are read here, and each of the scanner's keys is among them.
        let mut runner = proptest::test_runner::TestRunner::deterministic();
        let strategy = flat_line();
        let mut read = 0;
        for _ in 0..2000 {
            let text = strategy.new_tree(&mut runner).unwrap().current();
            let (fast, slow) = both(&text);
            if let Some(fast) = fast {
                read += 1;
                assert_eq!(Ok(fast), slow, "{text:?}");
            }
        }
        assert!(read > 300, "only {read} of 2000 lines took the fast path");
    }
}
