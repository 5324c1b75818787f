//! `sceneeval-fixtures [--out DIR]`: writes the fixtures folder (default: `fixtures/` at the
//! workspace root). See the library docs for what is written.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use sceneeval_files::ErrorChain;

const USAGE: &str = "usage: sceneeval-fixtures [--out DIR]\n\n\
    Writes procedural assets, sceneState scenes, expected answers and annotation rows into DIR\n\
    (default: the workspace's fixtures/ folder). The output is byte-identical on every run.\n";

enum Command {
    Generate(PathBuf),
    Help,
}

fn parse_args(mut args: impl Iterator<Item = String>) -> Result<Command, String> {
    let mut out = None;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "-h" | "--help" => return Ok(Command::Help),
            "--out" | "-o" => match args.next() {
                Some(dir) => out = Some(PathBuf::from(dir)),
                None => return Err("--out needs a directory".into()),
            },
            other => match other.strip_prefix("--out=") {
                Some(dir) => out = Some(PathBuf::from(dir)),
                None => return Err(format!("unexpected argument {other:?}")),
            },
        }
    }
    Ok(Command::Generate(
        out.unwrap_or_else(sceneeval_fixtures::default_output_dir),
    ))
}

fn main() -> ExitCode {
    // Write errors on stdout/stderr are ignored: there is nowhere else to report them.
    let dir = match parse_args(std::env::args().skip(1)) {
        Ok(Command::Generate(dir)) => dir,
        Ok(Command::Help) => {
            let _ = write!(std::io::stdout(), "{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            let _ = write!(std::io::stderr(), "error: {e}\n\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    match sceneeval_fixtures::generate(&dir) {
        Ok(generated) => {
            let _ = writeln!(
                std::io::stdout(),
                "wrote {} files ({} scenes) to {}",
                generated.files.len(),
                generated.expected.scenes.len(),
                dir.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "error: {:#}", ErrorChain::new(&e));
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn parse(args: &[&str]) -> Result<Command, String> {
        parse_args(args.iter().map(|s| s.to_string()))
    }

    #[test]
    fn arguments() {
        assert!(matches!(parse(&["--out", "x"]), Ok(Command::Generate(p)) if p == Path::new("x")));
        assert!(matches!(parse(&["--out=y"]), Ok(Command::Generate(p)) if p == Path::new("y")));
        assert!(matches!(parse(&[]), Ok(Command::Generate(p)) if p.ends_with("fixtures")));
        assert!(matches!(parse(&["--help"]), Ok(Command::Help)));
        assert!(parse(&["--out"]).is_err());
        assert!(parse(&["--bogus"]).is_err());
    }
}
