//! The studies of `signorini report` and `experiment` sharded in process, as `report --shard
//! k/3` and `merge` run them: the job lists of each, handed to three shards' executors and to
//! the merge of their files, make the files the local executor's results make, byte for byte
//! but for the wall-clock figures; and a merged study's wall time is the longest shard's time on
//! its list, not the merge's. The command line end to end is in `tests/cli/shards.rs` (the
//! whole report, ignored: `make test-report-shards`).

use std::path::{Path, PathBuf};

use crate::timings::assert_same_files_less_timings;
use signorini::harness::study::executor::{Batch, Executed, Executor};
use signorini::harness::study::shard::merge::merge;
use signorini::harness::study::shard::{Invocation, MergedJobs, ShardSpec};
use signorini::studies::error::Error;
use signorini::studies::experiment::{defaults_experiment, write_defaults_experiment};
use signorini::studies::gravity::{
    gravity_benchmark, write_gravity_report, GRAVITY_DIR, STUDY_JSON,
};
use signorini::studies::render::cross_section_pages;
use signorini::studies::report::{tables_report, write_report};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// An empty scratch directory of this test process named after `name`: its path.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "signorini-report-shards-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// What `plan` (a command's job lists, handed to a batch) makes under `executor`, which must
/// hand back every result.
fn complete<T>(
    executor: &Executor,
    plan: &dyn Fn(&mut Batch<'_>) -> Result<Option<T>, Error>,
) -> T {
    match executor.execute_lists(plan).unwrap() {
        Executed::Complete(value) => value,
        Executed::Share(_) => panic!("a local run or a merge hands back every result"),
    }
}

/// The merge of three shards, each run by `run` with its executor and written to its file as
/// `--shard k/3` does.
pub fn three_shards<T>(run: &dyn Fn(&Executor) -> Executed<T>) -> MergedJobs {
    let invocation = Invocation {
        command: "study".into(),
        arguments: vec![],
        request: String::new(),
        inputs: vec![],
    };
    let files = (1..=3)
        .map(|k| {
            let spec = ShardSpec { k, n: 3 };
            let Executed::Share(share) = run(&Executor::Shard(spec)) else {
                panic!("a shard hands back its share");
            };
            let file = invocation.shard_file(spec, share).unwrap();
            (PathBuf::from(format!("shard-{k}")), file)
        })
        .collect();
    merge(files).unwrap().jobs
}

/// Writes what `plan` makes locally into `dir/unsharded` and what the merge of its three shards
/// makes into `dir/merged`, asserts the two hold the same files less their wall-clock figures,
/// and returns the merged shards' lists and the merged directory.
fn merged_equals_unsharded<T>(
    name: &str,
    plan: &dyn Fn(&mut Batch<'_>) -> Result<Option<T>, Error>,
    write: &dyn Fn(&T, &Path) -> Result<(), Error>,
) -> (MergedJobs, PathBuf) {
    let dir = scratch(name);
    let (unsharded, merged) = (dir.join("unsharded"), dir.join("merged"));
    write(&complete(&Executor::Local, plan), &unsharded).unwrap();
    let jobs = three_shards(&|executor| executor.execute_lists(plan).unwrap());
    write(&complete(&Executor::Merge(jobs.clone()), plan), &merged).unwrap();
    assert!(assert_same_files_less_timings(&merged, &unsharded) > 0);
    (jobs, merged)
}

#[test]
fn the_merge_of_three_shards_of_the_gravity_benchmark_writes_its_unsharded_files() {
    let (jobs, merged) = merged_equals_unsharded(
        "gravity",
        &|batch| gravity_benchmark(root(), batch),
        &write_gravity_report,
    );
    // Three lists: the study, the ensembles, the figures' runs.
    assert_eq!(jobs.lists.len(), 3);
    let study: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(merged.join(GRAVITY_DIR).join(STUDY_JSON)).unwrap(),
    )
    .unwrap();
    assert_eq!(
        study["wall_seconds"].as_f64().unwrap(),
        jobs.lists[0].wall_seconds,
        "the merged study's wall time is its longest shard's"
    );
    assert!(jobs.lists[0].wall_seconds > 0.0);
}

/// The Tables 1–2 study, its sensitivity (14 cases × 7 levels × 17 runs), the longer horizon,
/// the implicit start and the histories: a few minutes on 2 cores, `make test-report-shards`.
#[test]
#[ignore = "the tables' studies twice, a few minutes: make test-report-shards"]
fn the_merge_of_three_shards_of_the_tables_writes_their_unsharded_files() {
    let (jobs, _) = merged_equals_unsharded(
        "tables",
        &|batch| tables_report(root(), batch),
        &|report, dir| {
            write_report(report, dir)?;
            // The pages the render step builds from these data (schemes.md, work-precision.md).
            for (name, text) in cross_section_pages(dir)?.rendered {
                std::fs::write(dir.join(name), text).unwrap();
            }
            Ok(())
        },
    );
    assert_eq!(jobs.lists.len(), 5);
}

/// The Tables 1–2 study at three horizons: `make test-report-shards`.
#[test]
#[ignore = "three Tables 1–2 studies twice: make test-report-shards"]
fn the_merge_of_three_shards_of_the_defaults_experiment_writes_its_unsharded_file() {
    let (jobs, _) = merged_equals_unsharded(
        "experiment",
        &|batch| defaults_experiment(root(), batch),
        &|experiment, dir| write_defaults_experiment(experiment, dir).map(|_| ()),
    );
    assert_eq!(jobs.lists.len(), 3);
}
