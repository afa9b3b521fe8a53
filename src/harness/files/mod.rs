//! The harness's files, whatever their format: how a file is read (regular files only, within a
//! size limit) and written (whole or not at all), how an output directory appears whole or not
//! at all and what proves the harness wrote it, and the harness's errors, which name the file.
//! The formats themselves (names, schema) belong to the part that writes them: a run's files to
//! [`crate::harness::run`], a golden file or a shard's to [`crate::harness::study`], each report
//! file to its study under `crate::studies`. The bottom part: it imports no other.
//!
//! | module | its face |
//! |---|---|
//! | [`input`] | [`input::open`], [`input::read_json`], [`input::Lines`]: every read, refused past its [`input::Limit`]; [`input::InputError`] |
//! | [`artifacts`] | [`artifacts::write_atomic`], [`artifacts::write_json`], [`artifacts::csv`]: every write, whole or not at all |
//! | [`output_dir`] | [`output_dir::StagedDir`]: an output directory staged beside its target and moved into place at the end |
//! | [`commit_journal`] | [`commit_journal::Journal`], [`commit_journal::complete`]: a commit of several renames recorded first, rolled forward by the next command if it was cut |
//! | [`fault`] | [`fault::step`]: every file operation of a commit, where the tests inject a fault |
//! | [`manifest`] | [`manifest::Manifest`]: the files a command wrote into a directory, with their SHA-256 |
//! | [`command_error`] | [`command_error::CommandError`]: how a command fails below the command line |
//! | [`error`] | [`error::Error`], the harness's error, and the errors it wraps ([`error::SceneError`], [`error::ShardError`], [`error::BudgetError`], …) |

pub mod artifacts;
pub mod commit_journal;
pub mod error;
pub mod fault;
pub mod input;
pub mod manifest;
pub mod output_dir;
