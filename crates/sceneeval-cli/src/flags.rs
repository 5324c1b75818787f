//! The old spellings of options. An option renamed to follow the command line's rules (a time
//! ends in `-s`, every writer takes `-o/--out`, every VLM option starts `--vlm-`, every image
//! side is `--render-size`) keeps its old name as a hidden alias (`Arg::alias`); a command line
//! that uses one works as before and gets a warning naming the new option. The rules are
//! tested on the whole command tree below.

use std::collections::BTreeMap;
use std::ffi::OsString;

/// The options of `command`'s subcommand that `matches` holds spelt the old way in `args` (the
/// command line, program name first): `(old, new)` long names without their `--`, in the
/// order given. An old spelling is a hidden alias of an option of the subcommand (or of one
/// of its parents); tokens after `--` are values, not options.
pub fn old_spellings(
    command: &clap::Command,
    matches: &clap::ArgMatches,
    args: &[OsString],
) -> Vec<(String, String)> {
    let mut renamed = BTreeMap::new();
    let mut add = |command: &clap::Command| {
        for arg in command.get_arguments() {
            let (Some(long), Some(all)) = (arg.get_long(), arg.get_all_aliases()) else {
                continue;
            };
            let visible = arg.get_visible_aliases().unwrap_or_default();
            for alias in all.into_iter().filter(|a| !visible.contains(a)) {
                renamed.insert(alias.to_owned(), long.to_owned());
            }
        }
    };
    add(command);
    let (mut command, mut matches) = (command, matches);
    while let Some((name, sub)) = matches.subcommand() {
        let Some(next) = command.find_subcommand(name) else {
            break;
        };
        add(next);
        (command, matches) = (next, sub);
    }
    args.iter()
        .skip(1)
        .map(|a| a.to_string_lossy())
        .take_while(|a| a != "--")
        .filter_map(|token| {
            let name = token.strip_prefix("--")?.split('=').next()?;
            renamed.get(name).map(|new| (name.to_owned(), new.clone()))
        })
        .collect()
}

/// The warning for an option spelt the old way.
pub fn old_spelling_warning(old: &str, new: &str) -> String {
    format!("warning: --{old} is the old name of --{new}; it still works, but use --{new}")
}

#[cfg(test)]
mod tests {
    use clap::{Args as _, CommandFactory};

    use super::*;

    /// Every command of the tree with its path (`["annotations", "generate"]`), leaves only.
    fn leaves(command: &clap::Command, path: Vec<String>, out: &mut Vec<(Vec<String>, clap::Command)>) {
        if command.get_subcommands().next().is_none() {
            out.push((path, command.clone()));
            return;
        }
        for sub in command.get_subcommands() {
            let mut p = path.clone();
            p.push(sub.get_name().to_owned());
            leaves(sub, p, out);
        }
    }

    fn commands() -> Vec<(String, clap::Command)> {
        let mut out = Vec::new();
        let mut cli = crate::Cli::command();
        cli.build();
        leaves(&cli, Vec::new(), &mut out);
        out.into_iter().map(|(p, c)| (p.join(" "), c)).collect()
    }

    fn visible_longs(command: &clap::Command) -> impl Iterator<Item = (&clap::Arg, &str)> {
        command
            .get_arguments()
            .filter(|a| !a.is_hide_set())
            .filter_map(|a| Some((a, a.get_long()?)))
    }

    fn help(arg: &clap::Arg) -> String {
        arg.get_help().map(ToString::to_string).unwrap_or_default()
    }

    /// The commands that write a file or folder.
    const WRITERS: [&str; 13] = [
        "convert",
        "render",
        "evaluate",
        "settle",
        "summarize",
        "ensemble",
        "compare",
        "agreement",
        "report",
        "judge",
        "annotations annotate",
        "annotations generate",
        "annotations review",
    ];

    /// The commands that print a machine-readable document.
    const DOCUMENTS: [&str; 5] = [
        "inspect",
        "annotations check",
        "annotations stats",
        "compare",
        "agreement",
    ];

    #[test]
    fn every_option_naming_a_time_ends_in_its_unit() {
        let mut times = Vec::new();
        for (path, command) in commands() {
            for (arg, long) in visible_longs(&command) {
                let text = help(arg).to_lowercase();
                let names_a_time = ["time", "budget", "duration", "delay", "interval"]
                    .iter()
                    .any(|w| long.contains(w))
                    || text.starts_with("seconds")
                    || text.contains(" in seconds");
                if names_a_time {
                    assert!(
                        long.ends_with("-s"),
                        "{path} --{long}: a time's option ends in -s"
                    );
                    times.push(format!("{path} --{long}"));
                }
            }
        }
        // The test sees them all (and would see a new one).
        for expected in [
            "evaluate --time-budget-s",
            "evaluate --vlm-timeout-s",
            "settle --time-budget-s",
            "settle --vlm-timeout-s",
            "annotations annotate --vlm-timeout-s",
            "annotations generate --vlm-timeout-s",
            "vlm check --vlm-timeout-s",
        ] {
            assert!(
                times.contains(&expected.to_owned()),
                "{expected} not found in {times:?}"
            );
        }
    }

    #[test]
    fn every_writer_takes_o_out() {
        let all = commands();
        for writer in WRITERS {
            let (_, command) = all
                .iter()
                .find(|(p, _)| p == writer)
                .unwrap_or_else(|| panic!("no command {writer}"));
            let out = command
                .get_arguments()
                .find(|a| a.get_long() == Some("out"))
                .unwrap_or_else(|| panic!("{writer} has no --out"));
            assert_eq!(out.get_short(), Some('o'), "{writer} --out has no -o");
        }
        for (path, command) in &all {
            for (arg, long) in visible_longs(command) {
                assert!(
                    !["output", "accepted", "out-dir", "out-file"].contains(&long),
                    "{path} --{long}: a writer's output is -o/--out"
                );
                if long == "out" {
                    assert_eq!(arg.get_short(), Some('o'), "{path}");
                    assert!(
                        WRITERS.contains(&path.as_str()),
                        "{path} writes: list it in WRITERS"
                    );
                }
            }
        }
    }

    #[test]
    fn machine_readable_output_is_chosen_by_format_and_every_image_side_is_render_size() {
        let all = commands();
        for (path, command) in &all {
            for (_, long) in visible_longs(command) {
                assert!(
                    !["json", "csv", "md", "markdown", "latex", "html", "text"].contains(&long),
                    "{path} --{long}: an output format is --format"
                );
                if long.contains("size") {
                    assert_eq!(long, "render-size", "{path}: an image side is --render-size");
                }
            }
            if DOCUMENTS.contains(&path.as_str()) {
                assert!(
                    command.get_arguments().any(|a| a.get_long() == Some("format")),
                    "{path} has no --format"
                );
            }
        }
        for render in ["render", "evaluate", "settle"] {
            let (_, command) = all.iter().find(|(p, _)| p == render).unwrap();
            assert!(
                command
                    .get_arguments()
                    .any(|a| a.get_long() == Some("render-size")),
                "{render}"
            );
        }
    }

    /// The `--vlm-*` options: one struct. Every command that asks a VLM has every option of
    /// [`crate::vlm::VlmEndpointArgs`]; a `--vlm-*` option has the same help, value name and
    /// default on every command that has it; and the commands that take the run limits
    /// (`--vlm-concurrency`, ...) take all of [`crate::vlm::VlmArgs`].
    #[test]
    fn the_vlm_options_are_one_set() {
        let longs = |command: clap::Command| -> Vec<String> {
            command
                .get_arguments()
                .filter_map(|a| a.get_long().map(str::to_owned))
                .collect()
        };
        let endpoint = longs(crate::vlm::VlmEndpointArgs::augment_args(clap::Command::new("e")));
        let run = longs(crate::vlm::VlmArgs::augment_args(clap::Command::new("r")));
        assert!(endpoint.iter().all(|l| l.starts_with("vlm-")), "{endpoint:?}");
        assert!(endpoint.contains(&"vlm-timeout-s".to_owned()));
        assert!(run.contains(&"vlm-concurrency".to_owned()));
        let mut seen: BTreeMap<String, (String, (String, String))> = BTreeMap::new();
        let mut asking = Vec::new();
        for (path, command) in commands() {
            let has = longs(command.clone());
            if has.contains(&"vlm-base-url".to_owned()) {
                asking.push(path.clone());
                for long in &endpoint {
                    assert!(has.contains(long), "{path} lacks --{long}");
                }
            }
            if has.contains(&"vlm-concurrency".to_owned()) {
                for long in &run {
                    assert!(has.contains(long), "{path} lacks --{long}");
                }
            }
            for arg in command.get_arguments() {
                let Some(long) = arg.get_long().filter(|l| l.starts_with("vlm-")) else {
                    continue;
                };
                let what = (
                    help(arg),
                    format!("{:?} {:?}", arg.get_value_names(), arg.get_default_values()),
                );
                match seen.get(long) {
                    Some((first, before)) => assert_eq!(&what, before, "--{long}: {path} and {first} differ"),
                    None => {
                        seen.insert(long.to_owned(), (path.clone(), what));
                    }
                }
            }
        }
        assert_eq!(
            asking,
            [
                "annotations annotate",
                "annotations generate",
                "evaluate",
                "settle",
                "vlm check"
            ]
        );
    }

    /// Old and new long names, as [`old_spellings`] gives them.
    type Renamed = &'static [(&'static str, &'static str)];

    /// The old spellings the command line had, each still accepted, each named with its new one.
    #[test]
    fn old_spellings_work_and_are_named() {
        let cases: [(&[&str], Renamed); 8] = [
            (
                &[
                    "evaluate",
                    "s",
                    "-o",
                    "o",
                    "--time-budget",
                    "5",
                    "--vlm-base-url",
                    "u",
                    "--vlm-model",
                    "m",
                    "--vlm-timeout=9",
                ],
                &[("time-budget", "time-budget-s"), ("vlm-timeout", "vlm-timeout-s")],
            ),
            (
                &["settle", "s.json", "-o", "o.json", "--time-budget", "5"],
                &[("time-budget", "time-budget-s")],
            ),
            (
                &[
                    "vlm",
                    "check",
                    "--base-url",
                    "u",
                    "--model",
                    "m",
                    "--timeout",
                    "3",
                    "--retries",
                    "0",
                    "--api-key-env",
                    "K",
                ],
                &[
                    ("base-url", "vlm-base-url"),
                    ("model", "vlm-model"),
                    ("timeout", "vlm-timeout-s"),
                    ("retries", "vlm-retries"),
                    ("api-key-env", "vlm-api-key-env"),
                ],
            ),
            (
                &[
                    "vlm",
                    "check",
                    "--vlm-base-url",
                    "u",
                    "--vlm-model",
                    "m",
                    "--vlm-timeout",
                    "3",
                ],
                &[("vlm-timeout", "vlm-timeout-s")],
            ),
            (
                &["render", "s.json", "-o", "d", "--size", "8"],
                &[("size", "render-size")],
            ),
            (
                &["annotations", "review", "f.csv", "--accepted", "a.csv"],
                &[("accepted", "out")],
            ),
            (
                &[
                    "annotations",
                    "generate",
                    "--examples",
                    "e.csv",
                    "--count",
                    "1",
                    "-o",
                    "o.csv",
                    "--first-id",
                    "3",
                    "--vlm-base-url",
                    "u",
                    "--vlm-model",
                    "m",
                ],
                &[("first-id", "id")],
            ),
            // The new names, and a value after `--`, are not old spellings.
            (
                &[
                    "evaluate",
                    "-o",
                    "o",
                    "--time-budget-s",
                    "5",
                    "--",
                    "--time-budget",
                ],
                &[],
            ),
        ];
        let command = crate::Cli::command();
        for (args, expected) in cases {
            let argv: Vec<OsString> = std::iter::once("sceneeval")
                .chain(args.iter().copied())
                .map(OsString::from)
                .collect();
            let matches = command
                .clone()
                .try_get_matches_from(&argv)
                .unwrap_or_else(|e| panic!("{args:?}: {e}"));
            let found = old_spellings(&command, &matches, &argv);
            let expected: Vec<(String, String)> = expected
                .iter()
                .map(|(o, n)| ((*o).to_owned(), (*n).to_owned()))
                .collect();
            assert_eq!(found, expected, "{args:?}");
        }
        assert_eq!(
            old_spelling_warning("time-budget", "time-budget-s"),
            "warning: --time-budget is the old name of --time-budget-s; it still works, but use --time-budget-s"
        );
    }
}
