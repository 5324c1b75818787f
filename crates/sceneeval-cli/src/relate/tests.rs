use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

use serde_json::Value;

use super::*;

fn session() -> Session {
    Session::new(RelationParams::default(), AssetLibrary::new(), 8)
}

/// A writer that records what reaches it and how often it is written to and flushed.
#[derive(Debug, Default)]
struct Counting {
    bytes: Vec<u8>,
    writes: usize,
    flushes: usize,
}

#[derive(Debug, Clone, Default)]
struct Shared(Rc<RefCell<Counting>>);

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let mut c = self.0.borrow_mut();
        c.writes += 1;
        c.bytes.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.0.borrow_mut().flushes += 1;
        Ok(())
    }
}

/// A reader handing out one chunk per read, as a pipe does when the client writes one chunk
/// and waits; before each chunk it records how many answer lines had reached the writer.
struct Chunks {
    chunks: VecDeque<Vec<u8>>,
    pending: Vec<u8>,
    written: Shared,
    answers_seen: Vec<usize>,
}

impl Read for Chunks {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.pending.is_empty() {
            let Some(next) = self.chunks.pop_front() else {
                return Ok(0);
            };
            let lines = self
                .written
                .0
                .borrow()
                .bytes
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            self.answers_seen.push(lines);
            self.pending = next;
        }
        let n = buf.len().min(self.pending.len());
        buf[..n].copy_from_slice(&self.pending[..n]);
        self.pending.drain(..n);
        Ok(n)
    }
}

fn box_query(i: usize) -> String {
    format!(
        r#"{{"id":{i},"relation":"next_to","target":{{"center":[{},0,0.5],"half_size":[0.5,0.5,0.5],"yaw":0}},"anchor":{{"center":[0,0,0.5],"half_size":[0.5,0.5,0.5],"yaw":0}}}}"#,
        1.0 + (i % 7) as f64 * 0.1
    )
}

#[test]
fn an_interactive_client_gets_each_answer_before_it_writes_the_next_line() {
    let written = Shared::default();
    let mut input = Chunks {
        // One line per chunk; the third is split in two to show a half-written line waits too.
        chunks: VecDeque::from(vec![
            format!("{}\n", box_query(0)).into_bytes(),
            format!("{}\n", box_query(1)).into_bytes(),
            box_query(2).as_bytes()[..40].to_vec(),
            format!("{}\n", &box_query(2)[40..]).into_bytes(),
        ]),
        pending: Vec::new(),
        written: written.clone(),
        answers_seen: Vec::new(),
    };
    let mut out = BufWriter::with_capacity(BUFFER_BYTES, written.clone());
    let failed = answer_all(&mut input, &mut out, &mut session()).unwrap();
    assert_eq!(failed, 0);
    // Before reading chunk k the answers to every complete line before it had been written.
    assert_eq!(input.answers_seen, [0, 1, 2, 2]);
    let text = String::from_utf8(written.0.borrow().bytes.clone()).unwrap();
    assert_eq!(text.lines().count(), 3);
}

#[test]
fn a_large_input_is_answered_in_few_writes() {
    let n = 20_000;
    let text: String = (0..n).map(|i| box_query(i) + "\n").collect();
    let written = Shared::default();
    let mut out = BufWriter::with_capacity(BUFFER_BYTES, written.clone());
    let failed = answer_all(text.as_bytes(), &mut out, &mut session()).unwrap();
    assert_eq!(failed, 0);
    let c = written.0.borrow();
    let answers = String::from_utf8(c.bytes.clone()).unwrap();
    assert_eq!(answers.lines().count(), n);
    // In order: answer i has id i.
    for (i, a) in answers.lines().enumerate().step_by(997) {
        assert!(a.starts_with(&format!(r#"{{"id":{i},"score":"#)), "{a}");
    }
    // A slice answers every read at once: one flush per 64 KiB refill of the input (plus the
    // read that finds its end, and the last flush), one write per flush or 64 KiB of output;
    // never one per line.
    let refills = text.len().div_ceil(BUFFER_BYTES);
    assert!(
        c.flushes <= refills + 2,
        "{} flushes for {refills} refills",
        c.flushes
    );
    let bound = refills + 2 + answers.len().div_ceil(BUFFER_BYTES);
    assert!(
        c.writes <= bound,
        "{} writes for {n} lines (bound {bound})",
        c.writes
    );
    assert!(bound < n / 100);
}

#[test]
fn declared_and_inline_rooms_give_the_same_bits_and_are_prepared_once() {
    let room = r#"{"floor":[[0,0],[4,0],[4,5],[0,5]],"openings":[{"kind":"door","wall":0,"along":[1.0,1.9],"height":[0.0,2.1]}]}"#;
    let target = r#"{"center":[2.1,4.0,0.3],"half_size":[0.8,1.0,0.3],"yaw":0.05}"#;
    let relations = [
        r#""relation":"against_wall""#,
        r#""relation":"near","arch":"door""#,
        r#""relation":"corner_of_room""#,
        r#""relation":"middle_of_room""#,
    ];
    let mut s = session();
    let mut lines = vec![format!(r#"{{"declare":"bedroom","room":{room}}}"#)];
    lines.push(format!(r#"{{"declare":"bed","object":{target}}}"#));
    for r in relations {
        lines.push(format!(r#"{{{r},"target":{target},"room":{room}}}"#));
        lines.push(format!(r#"{{{r},"target":"bed","room":"bedroom"}}"#));
        lines.push(format!(r#"{{{r},"target":{target},"room":{room}}}"#));
    }
    let answers: Vec<Value> = lines
        .iter()
        .enumerate()
        .map(|(i, l)| serde_json::to_value(answer_line(l, i + 1, &mut s)).unwrap())
        .collect();
    for (k, relation) in relations.iter().enumerate() {
        let [a, b, c] = [2 + 3 * k, 3 + 3 * k, 4 + 3 * k].map(|i| answers[i]["score"].as_f64().unwrap());
        assert_eq!(a.to_bits(), b.to_bits(), "{relation}");
        assert_eq!(a.to_bits(), c.to_bits(), "{relation}");
    }
    // The declaration and the inline copies share one prepared room.
    assert_eq!(s.rooms_built(), 1);
}

#[test]
fn lines_split_across_reads_are_answered_as_whole_ones() {
    // Blank lines, an error, bytes that are not UTF-8, a CRLF line and a last line without a
    // newline: read in chunks of every size from 1 byte, the answers are the bytes of one read.
    let mut input = Vec::new();
    for i in 0..6 {
        input.extend_from_slice(box_query(i).as_bytes());
        input.extend_from_slice(if i == 2 { b"\r\n\n  \n" } else { b"\n" });
    }
    input.extend_from_slice(b"{\"id\":\"x\xff\"}\n{\"id\":9,\"relation\":\"beside\"}\n");
    input.extend_from_slice(box_query(6).as_bytes());
    let run = |chunk: usize| {
        let written = Shared::default();
        let mut reader = Chunks {
            chunks: input.chunks(chunk).map(<[u8]>::to_vec).collect(),
            pending: Vec::new(),
            written: written.clone(),
            answers_seen: Vec::new(),
        };
        let mut out = BufWriter::with_capacity(BUFFER_BYTES, written.clone());
        let failed = answer_all(&mut reader, &mut out, &mut session()).unwrap();
        drop(out);
        let bytes = written.0.borrow().bytes.clone();
        (failed, String::from_utf8(bytes).unwrap())
    };
    let (failed, whole) = run(input.len());
    assert_eq!(failed, 2);
    assert_eq!(whole.lines().count(), 9, "{whole}");
    assert!(whole.contains(r#""error":"line 9: not UTF-8"#), "{whole}");
    assert!(whole.contains(r#"{"id":9,"error":"line 10: "#), "{whole}");
    assert!(whole.ends_with("\n") && whole.lines().last().unwrap().starts_with(r#"{"id":6,"#));
    for chunk in 1..=13 {
        assert_eq!(run(chunk), (failed, whole.clone()), "chunks of {chunk} bytes");
    }
}
