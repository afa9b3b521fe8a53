//! What the user meets: the `signorini` binary end to end (exit codes, messages, whole files),
//! the committed scene files, the box scenes' VTK output and its ParaView collection, and the
//! SVG figures and their index.

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/external.rs"]
mod external_runs;
#[path = "../common/watched.rs"]
mod watched;

mod commands;
mod elastic;
mod figures;
mod getfem;
mod hostile;
mod outputs;
mod paraview;
mod reliability;
mod report_figures;
mod scenes;
mod shards;
mod verify;
