//! What the user meets: the `signorini` binary end to end (exit codes, messages, whole files),
//! the committed scene files, the box scenes' VTK output and its ParaView collection, the SVG
//! figures and their index, and the links of the README and the book (docs/).

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/external.rs"]
mod external_runs;
#[path = "../common/timings.rs"]
mod timings;
#[path = "../common/watched.rs"]
mod watched;

mod commands;
mod commit_faults;
mod docs;
mod elastic;
mod figure_geometry;
mod figures;
mod getfem;
mod getfem_box;
mod hostile;
mod hostile_paraview;
mod hostile_round4;
mod league;
mod outputs;
mod paraview;
mod physics;
mod progress;
mod readme_commands;
mod real_codes;
mod reliability;
mod report_figures;
mod scenes;
mod shards;
mod tutorial;
mod verify;
mod verify_box;
mod verify_format2;
mod verify_mesh;
mod vocabulary;
