//! `sceneeval relate`: answers spatial-relation queries given as JSON lines, one answer line
//! per non-blank input line, so that any language can use the predicates.
//!
//! The line schema (version 1) is documented in `docs/formats.md` ("`sceneeval relate` JSON
//! lines"): queries, and declarations of named objects (boxes or mesh assets from
//! `--assets`) and rooms that later queries refer to by name. A line that cannot be answered
//! gets `{"id": ..., "error": "..."}` (the id when it could be read, else `null`) and
//! processing goes on. Blank lines are skipped. Exit status: 0 when every line was answered
//! without error, 2 when some line got an error answer, 1 when the input could not be read at
//! all.
//!
//! This command is the framing of a query stream: it reads lines, numbers them and hands each
//! to `sceneeval::relate::answer_line`, which parses it (the one reader of the line format),
//! asks the `sceneeval::relate::Session` (declared names, prepared rooms, the asset library,
//! scoring through the one dispatcher; the Python package goes through the same session type)
//! and gives the answer it writes.
//!
//! Speed: each line is parsed once into borrowed, typed fields (a query by name through a
//! scanner of its own, every other line through serde_json); the session prepares rooms once
//! per distinct room text, so an inline room costs what a declared one costs; answers are
//! buffered and flushed only when the input has nothing more to read at once (see
//! [`answer_all`]).

use std::fs::File;
use std::io::{self, BufRead, BufReader, BufWriter, Read, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::io::AssetLibrary;
use sceneeval::relate::{Answer, RawText, Session, answer_line, write_answer};
use sceneeval::relations::RelationParams;

/// Size of the input and output buffers.
const BUFFER_BYTES: usize = 1 << 16;

/// Arguments of `sceneeval relate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Read queries from this file instead of standard input (one JSON object per line).
    #[arg(long, short, value_name = "FILE")]
    pub input: Option<PathBuf>,
    /// Use the reference implementation's behaviour where it differs from the paper
    /// (`on_top` from the centre plane, `surround` with the median, `corner_of_room` from mean
    /// directions, `middle_of_room` from the bounds centre, distances from the smaller box).
    #[arg(long)]
    pub reference: bool,
    /// Asset folder for a model-id prefix, as `PREFIX=DIR` (layout chosen from the prefix) or
    /// `PREFIX=LAYOUT:DIR` with LAYOUT one of 3d-future, objathor, hssd, layoutvlm, idesign,
    /// scene-agent, plain: objects may then name an asset (`"asset": "PREFIX.ID"`) instead of
    /// being boxes. Repeat for several prefixes.
    #[arg(long = "assets", value_name = "PREFIX=[LAYOUT:]DIR")]
    pub assets: Vec<String>,
    /// How many distinct rooms written in place (not declared) stay prepared at once; the
    /// least recently used is dropped beyond that.
    #[arg(long, value_name = "N", default_value_t = 256)]
    pub room_cache: usize,
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let params = if args.reference {
        RelationParams::reference()
    } else {
        RelationParams::default()
    };
    let assets = AssetLibrary::from_specs(&args.assets).context("invalid --assets")?;
    let mut session = Session::new(params, assets, args.room_cache);
    let stdout = io::stdout();
    let mut out = BufWriter::with_capacity(BUFFER_BYTES, stdout.lock());
    let failed = match &args.input {
        Some(path) => {
            let file = File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
            answer_all(file, &mut out, &mut session).with_context(|| format!("reading {}", path.display()))?
        }
        None => answer_all(io::stdin().lock(), &mut out, &mut session).context("reading standard input")?,
    };
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        tracing::warn!(failed, "some lines could not be answered");
        ExitCode::from(2)
    })
}

/// Answers every line of `input` into `out`; returns how many lines got an error answer.
///
/// `out` is flushed whenever the next read would have to wait for more input (the input
/// buffer is empty), and at the end: a client that writes a line and waits gets its answer,
/// and a file or a fast producer is answered in large writes. A line that lies whole in the
/// input buffer is answered where it lies; one split across reads is gathered first.
fn answer_all(input: impl Read, out: &mut impl Write, session: &mut Session) -> anyhow::Result<usize> {
    let mut input = BufReader::with_capacity(BUFFER_BYTES, input);
    let mut stream = Stream {
        session,
        number: 0,
        failed: 0,
    };
    let mut split = Vec::new();
    loop {
        if input.buffer().is_empty() {
            out.flush()?;
        }
        let available = match input.fill_buf() {
            Ok(available) => available,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e.into()),
        };
        if available.is_empty() {
            break;
        }
        let used = match memchr::memchr(b'\n', available) {
            Some(end) if split.is_empty() => {
                stream.answer(&available[..=end], out)?;
                end + 1
            }
            Some(end) => {
                split.extend_from_slice(&available[..=end]);
                stream.answer(&split, out)?;
                split.clear();
                end + 1
            }
            None => {
                split.extend_from_slice(available);
                available.len()
            }
        };
        input.consume(used);
    }
    if !split.is_empty() {
        stream.answer(&split, out)?;
    }
    out.flush()?;
    Ok(stream.failed)
}

/// The session of a stream, and its count of lines and of error answers.
struct Stream<'s> {
    session: &'s mut Session,
    /// Lines read so far.
    number: usize,
    /// Lines answered with an error.
    failed: usize,
}

impl Stream<'_> {
    /// Answers the next line (its bytes, with its newline if any) into `out`.
    fn answer(&mut self, line: &[u8], out: &mut impl Write) -> io::Result<()> {
        self.number += 1;
        let number = self.number;
        let answer = match std::str::from_utf8(line) {
            Ok(text) if text.trim_ascii().is_empty() => return Ok(()),
            Ok(text) => answer_line(text, number, self.session),
            Err(e) => Answer::error(RawText::NULL, format!("not UTF-8: {e}")),
        };
        let answer = match answer {
            Answer::Error { id, error } => {
                self.failed += 1;
                Answer::Error {
                    id,
                    error: format!("line {number}: {error}"),
                }
            }
            ok => ok,
        };
        write_answer(out, &answer)
    }
}

#[cfg(test)]
mod tests;
