//! The command line this process was given, read once by `main.rs` and handed down: what a
//! report says it was made by, what a shard records as typed, and what a merge says it stands
//! for.

use std::path::Path;

/// The options that the shards of one invocation may give differently: dropped from the
/// arguments a shard records (`--out` is the merge's to give).
const PER_SHARD_OPTIONS: [&str; 2] = ["--shard", "--out"];

/// A command line as a user types it, less the program's name: the subcommand, then its
/// arguments.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CommandLine {
    arguments: Vec<String>,
}

impl CommandLine {
    /// The command line of `arguments` (the program's name left out).
    pub fn new(arguments: Vec<String>) -> Self {
        Self { arguments }
    }

    /// The command line a merge of `command`'s shards stands for: the subcommand, the arguments
    /// its shards recorded, and the merge's `--out` when given.
    pub fn of_merge(command: &str, recorded: &[String], out: Option<&Path>) -> Self {
        let mut arguments = vec![command.to_string()];
        arguments.extend(recorded.iter().cloned());
        if let Some(out) = out {
            arguments.extend(["--out".to_string(), out.display().to_string()]);
        }
        Self { arguments }
    }

    /// The subcommand (empty when none is given).
    pub fn subcommand(&self) -> &str {
        self.arguments.first().map_or("", String::as_str)
    }

    /// The line as a user types it: `signorini` and the arguments.
    pub fn typed(&self) -> String {
        std::iter::once("signorini")
            .chain(self.arguments.iter().map(String::as_str))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The arguments after the subcommand, less [`PER_SHARD_OPTIONS`] and their values: what
    /// every shard of one invocation records alike.
    pub fn shard_arguments(&self) -> Vec<String> {
        let mut kept = Vec::new();
        let mut args = self.arguments.iter().skip(1);
        while let Some(a) = args.next() {
            if PER_SHARD_OPTIONS.contains(&a.as_str()) {
                args.next();
            } else if !PER_SHARD_OPTIONS
                .iter()
                .any(|o| a.starts_with(&format!("{o}=")))
            {
                kept.push(a.clone());
            }
        }
        kept
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(words: &str) -> CommandLine {
        CommandLine::new(words.split(' ').map(String::from).collect())
    }

    #[test]
    fn a_shard_records_its_arguments_less_the_per_shard_options() {
        let typed = line("study s.json --shard 2/3 --levels 10,20 --out=o --out d");
        assert_eq!(typed.subcommand(), "study");
        assert_eq!(typed.shard_arguments(), ["s.json", "--levels", "10,20"]);
    }

    #[test]
    fn a_merge_stands_for_the_unsharded_line_with_its_out() {
        let recorded = ["s.json".to_string(), "--json".to_string()];
        let merged = CommandLine::of_merge("study", &recorded, Some(Path::new("r")));
        assert_eq!(merged.typed(), "signorini study s.json --json --out r");
        assert_eq!(merged.shard_arguments(), recorded);
    }
}
