//! `--format`, the one option of every command that can print a machine-readable document
//! (`inspect`, `annotations check`, `annotations stats`); `--json` stays as its alias.

/// What a command prints.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Text for people: aligned tables, one finding per line.
    #[default]
    Text,
    /// One JSON document.
    Json,
}

/// The `--format` option (and its alias `--json`).
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct FormatArgs {
    /// What to print: `text` (default) or `json` (one JSON document).
    #[arg(long, value_enum, value_name = "text|json", default_value_t = Format::Text)]
    pub format: Format,
    /// The same as `--format json`.
    #[arg(long, hide = true, conflicts_with = "format")]
    pub json: bool,
}

impl FormatArgs {
    /// Whether JSON is asked for (`--format json` or `--json`, which prints a warning naming
    /// `--format json`).
    pub fn json(&self) -> bool {
        if self.json {
            eprintln!("{}", crate::flags::old_spelling_warning("json", "format json"));
        }
        self.json || self.format == Format::Json
    }
}
