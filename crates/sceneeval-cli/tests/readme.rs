//! Every `sceneeval` command line the README quotes, in its shell blocks and in its inline code,
//! is given to the real binary: a renamed command or flag fails here, not in a user's terminal.
//!
//! Each line is parsed by the binary with `--help` appended (clap checks the subcommand and
//! every option before `--help` answers, without needing the data the line names), and the lines
//! that use only the bundled fixtures are run for real, their outputs redirected into a temporary
//! folder.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;

/// The README of the repository.
fn readme() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md")).unwrap()
}

/// A quoted command line: the README's line number and its words (after `sceneeval`).
#[derive(Debug, Clone)]
struct Quoted {
    line: usize,
    text: String,
    words: Vec<String>,
}

/// The shell words of `text` (single and double quotes, no expansion), `None` for a line that
/// is not a `sceneeval` command line (after `cargo run ... --` for the development form).
fn sceneeval_words(text: &str) -> Option<Vec<String>> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut quote = None;
    let mut in_word = false;
    for c in text.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                in_word = true;
            }
            (None, c) if c.is_whitespace() => {
                if in_word {
                    words.push(std::mem::take(&mut word));
                    in_word = false;
                }
            }
            (None, c) => {
                word.push(c);
                in_word = true;
            }
        }
    }
    if in_word {
        words.push(word);
    }
    let start = match words.first().map(String::as_str) {
        Some("sceneeval") => 1,
        Some("cargo") => words.iter().position(|w| w == "--")? + 1,
        _ => return None,
    };
    if start == 1 && words.len() == 1 {
        return None;
    }
    Some(words.split_off(start))
}

/// Every `sceneeval` command line of `readme`: the lines of its `sh` blocks (continuations
/// joined) and its inline code spans that start with `sceneeval ` (spans may wrap lines).
fn quoted_lines(readme: &str) -> Vec<Quoted> {
    let mut out = Vec::new();
    let mut prose = String::new();
    let mut prose_lines = Vec::new();
    let mut in_block: Option<bool> = None; // Some(true): a sh block
    let mut pending: Option<(usize, String)> = None;
    for (i, line) in readme.lines().enumerate() {
        let number = i + 1;
        if let Some(rest) = line.strip_prefix("```") {
            in_block = match in_block {
                Some(_) => None,
                None => Some(rest.trim() == "sh"),
            };
            prose.push('\n');
            prose_lines.push(number);
            continue;
        }
        match in_block {
            Some(true) => {
                let trimmed = line.trim();
                if trimmed.starts_with('#') {
                    continue;
                }
                let (start, mut text) = pending.take().unwrap_or((number, String::new()));
                match trimmed.strip_suffix('\\') {
                    Some(head) => {
                        text.push_str(head);
                        text.push(' ');
                        pending = Some((start, text));
                    }
                    None => {
                        text.push_str(trimmed);
                        if let Some(words) = sceneeval_words(&text) {
                            out.push(Quoted {
                                line: start,
                                text,
                                words,
                            });
                        }
                    }
                }
            }
            Some(false) => {}
            None => {
                // Inline code: the prose with each line's start remembered, so a span that
                // wraps is read whole.
                for _ in line.chars().chain(std::iter::once('\n')) {
                    prose_lines.push(number);
                }
                prose.extend(line.chars().chain(std::iter::once('\n')));
            }
        }
        if in_block.is_none() {
            continue;
        }
        prose.push('\n');
        prose_lines.push(number);
    }
    let chars: Vec<char> = prose.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        if chars[i] != '`' {
            i += 1;
            continue;
        }
        let Some(len) = chars[i + 1..].iter().position(|&c| c == '`') else {
            break;
        };
        let span: String = chars[i + 1..i + 1 + len].iter().collect();
        let span = span.replace('\n', " ");
        if span.starts_with("sceneeval ")
            && let Some(words) = sceneeval_words(&span)
        {
            out.push(Quoted {
                line: prose_lines[i],
                text: span,
                words,
            });
        }
        i += len + 2;
    }
    out
}

/// `words` as a line to parse: optional parts (`[--json]`) kept without their brackets, `...`
/// (elided arguments, `a,...` lists) left out, shell variables and the number placeholder `N`
/// given a value, and of alternatives (`easy|medium|hard`) the first.
fn to_parse(words: &[String]) -> Vec<String> {
    variants(words).swap_remove(0)
}

/// The lines [`to_parse`] makes of `words`, one for each alternative of each word that offers
/// several (`annotate|generate|review`), the other words at their first: every alternative
/// the README names is checked.
fn variants(words: &[String]) -> Vec<Vec<String>> {
    let cleaned: Vec<String> = words
        .iter()
        .filter(|w| w.as_str() != "..." && w.as_str() != "[...]")
        .map(|w| {
            let w = w.strip_prefix('[').unwrap_or(w);
            let w = w.strip_suffix(']').unwrap_or(w);
            let w = w.strip_suffix(",...").unwrap_or(w);
            let w = w
                .replace("${SLURM_ARRAY_TASK_ID}", "1")
                .replace("$VLM_URL", "http://127.0.0.1:9/v1")
                .replace("$VLM_MODEL", "model");
            match w.as_str() {
                "N" => "1".to_owned(),
                _ => w,
            }
        })
        .collect();
    let alternatives = |w: &str| -> Vec<String> {
        match w.contains('|') && !w.contains("://") {
            true => w.split('|').map(str::to_owned).collect(),
            false => vec![w.to_owned()],
        }
    };
    let first: Vec<String> = cleaned.iter().map(|w| alternatives(w).swap_remove(0)).collect();
    let mut out = vec![first.clone()];
    for (i, w) in cleaned.iter().enumerate() {
        for alternative in alternatives(w).into_iter().skip(1) {
            let mut line = first.clone();
            line[i] = alternative;
            out.push(line);
        }
    }
    out
}

#[test]
fn the_readme_quotes_command_lines_of_every_kind() {
    let lines = quoted_lines(&readme());
    // The blocks and the prose both quote commands; a parser that found none would pass the
    // test below without checking anything.
    assert!(lines.len() >= 30, "{} lines: {lines:#?}", lines.len());
    for command in [
        "evaluate",
        "convert",
        "summarize",
        "compare",
        "report",
        "render",
        "inspect",
        "settle",
        "relate",
        "annotations",
        "judge",
        "vlm",
    ] {
        assert!(
            lines
                .iter()
                .any(|q| q.words.first().map(String::as_str) == Some(command)),
            "no quoted `sceneeval {command}` line"
        );
    }
}

#[test]
fn every_command_line_in_the_readme_parses() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for q in quoted_lines(&readme()) {
        for mut args in variants(&q.words) {
            // Prose that names an option of a command (`sceneeval evaluate --plan`): the
            // command's help must list it.
            let named = match args.last() {
                Some(last)
                    if last.starts_with("--")
                        && args.len() >= 2
                        && q.text.trim_end().ends_with(last.as_str()) =>
                {
                    args.pop()
                }
                _ => None,
            };
            args.push("--help".into());
            let output = Command::cargo_bin("sceneeval")
                .unwrap()
                .args(&args)
                .output()
                .unwrap();
            let help = String::from_utf8_lossy(&output.stdout);
            let listed = named.as_ref().is_none_or(|option| {
                help.split(|c: char| !(c.is_alphanumeric() || c == '-'))
                    .any(|w| w == option)
            });
            checked += 1;
            if !output.status.success() || !listed {
                failures.push(format!(
                    "README.md:{}: `sceneeval {}` ({})\n  {}",
                    q.line,
                    q.text.trim_start_matches("sceneeval "),
                    args.join(" "),
                    match output.status.success() {
                        true => format!("{} is not an option of this command", named.unwrap_or_default()),
                        false => String::from_utf8_lossy(&output.stderr).trim().to_owned(),
                    }
                ));
            }
        }
    }
    assert!(checked >= 30, "{checked}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The line's words with each `--out` / `-o` value moved into `dir` (the same relative path).
fn redirect_outputs(words: &[String], dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut next_is_out = false;
    for w in to_parse(words) {
        if next_is_out {
            out.push(dir.join(&w).display().to_string());
        } else {
            out.push(w.clone());
        }
        next_is_out = w == "--out" || w == "-o";
    }
    out
}

/// Whether every path-like word of the line (but its outputs) names something of the
/// repository: the lines that run on the bundled fixtures.
fn uses_only_fixtures(words: &[String], root: &Path) -> bool {
    let mut inputs = 0;
    let mut previous = "";
    for w in words {
        let value = w.rsplit_once('=').map_or(w.as_str(), |(_, v)| v);
        if (previous != "--out" && previous != "-o") && value.contains('/') {
            if !root.join(value).exists() {
                return false;
            }
            inputs += 1;
        }
        previous = w;
    }
    inputs > 0
}

#[test]
fn the_readme_command_lines_on_the_fixtures_run() {
    let root: PathBuf = common::fixtures().join("..");
    let lines: Vec<Quoted> = quoted_lines(&readme())
        .into_iter()
        .filter(|q| uses_only_fixtures(&to_parse(&q.words), &root))
        .collect();
    let commands: Vec<&str> = lines.iter().map(|q| q.words[0].as_str()).collect();
    // The quick start's evaluate, the full plan and the renderer at least.
    assert!(
        commands.iter().filter(|c| **c == "evaluate").count() >= 2,
        "{lines:#?}"
    );
    assert!(commands.contains(&"render"), "{lines:#?}");
    let rendering = common::renderer().is_some();
    let dir = tempfile::tempdir().unwrap();
    for q in &lines {
        if q.words[0] == "render" && !rendering {
            continue; // said once by `common::renderer`
        }
        let mut args = redirect_outputs(&q.words, dir.path());
        if q.words[0] == "evaluate" {
            args.push("--no-progress".into());
        }
        let output = Command::cargo_bin("sceneeval")
            .unwrap()
            .current_dir(&root)
            .args(&args)
            .output()
            .unwrap();
        assert!(
            output.status.success(),
            "README.md:{}: `sceneeval {}` failed:\n{}",
            q.line,
            args.join(" "),
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

#[test]
fn inline_code_that_wraps_is_read_whole_and_blocks_join_continuations() {
    let text = "Run `sceneeval summarize a b\n--out c` then.\n\n```sh\n# a comment\nsceneeval evaluate x \\\n    --out y\ncargo run -p sceneeval-cli -- render s.json [--size 512]\n```\n\n```json\n{\"sceneeval \": 1}\n```\n`sceneeval-render` is a crate.\n";
    let lines = quoted_lines(text);
    let words: Vec<Vec<String>> = lines.iter().map(|q| q.words.clone()).collect();
    let expected: Vec<Vec<&str>> = vec![
        vec!["evaluate", "x", "--out", "y"],
        vec!["render", "s.json", "[--size", "512]"],
        vec!["summarize", "a", "b", "--out", "c"],
    ];
    assert_eq!(words, expected);
    assert_eq!(lines.iter().map(|q| q.line).collect::<Vec<_>>(), vec![6, 8, 1]);
    assert_eq!(
        to_parse(&lines[1].words),
        vec!["render", "s.json", "--size", "512"]
    );
    let words: Vec<String> = [
        "annotations",
        "a|b",
        "--count",
        "N",
        "--objects",
        "x,...",
        "[--d",
        "easy|hard]",
    ]
    .map(str::to_owned)
    .to_vec();
    let lines: Vec<String> = variants(&words).iter().map(|l| l.join(" ")).collect();
    assert_eq!(
        lines,
        vec![
            "annotations a --count 1 --objects x --d easy",
            "annotations b --count 1 --objects x --d easy",
            "annotations a --count 1 --objects x --d hard",
        ]
    );
}
