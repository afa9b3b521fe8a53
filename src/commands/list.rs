//! `signorini list`: the schemes, mass variants, contact treatments, norms and scenes.

use std::path::{Path, PathBuf};

use clap::Args;

use super::failure::Failure;
use crate::harness::problem::{MassVariant, Scheme, TREATMENT_LIST};
use crate::harness::run::norms::Norm;
use crate::harness::study::scene::{scene_files, Scene};

/// The arguments of `signorini list`.
#[derive(Debug, Args)]
pub struct ListArgs {
    /// Where to look for scene files.
    #[arg(long, default_value = "scenes")]
    pub scenes: PathBuf,
}

/// The schemes with their parameters, the mass variants, the norms and the scenes found.
pub fn list(args: ListArgs) -> Result<(), Failure> {
    let ListArgs { scenes } = args;
    print_list(&scenes);
    Ok(())
}

fn print_list(dir: &Path) {
    out!("Schemes (preset name, parameters, the paper's name):");
    for (name, scheme, label) in Scheme::presets() {
        let params = match scheme {
            Scheme::Newmark { beta, gamma } => format!("Newmark β = {beta}, γ = {gamma}"),
            Scheme::Theta { theta } => format!("θ-method θ = {theta}"),
            Scheme::PaoliSchatzman { beta, restitution } => {
                format!("Paoli–Schatzman β = {beta}, e = {restitution}")
            }
        };
        out!("  {name:22} {params:34} {label}");
    }
    out!("  any parameters: newmark(beta=B,gamma=G), theta(theta=T), paoli-schatzman(beta=B,e=E)");
    out!("\nMass variants:");
    for m in MassVariant::ALL {
        out!(
            "  {:25} {:5} {}",
            m.name(),
            m.paper_label(),
            m.description()
        );
    }
    out!("\nContact treatments (E the Young modulus, ρc² for a bar; h the mesh size at the contact):");
    for (name, params, description) in TREATMENT_LIST {
        out!("  {name:27} {params:22} {description}");
    }
    out!("\nNorms:");
    for n in Norm::ALL {
        out!("  {:12} {}", n.key(), n.label());
    }
    out!("\nScenes in {}:", dir.display());
    let files = scene_files(dir);
    if files.is_empty() {
        out!("  (none)");
    }
    for f in files {
        match Scene::load(&f) {
            Ok(s) => out!("  {:40} {}", f.display(), s.description),
            Err(e) => out!("  {:40} INVALID: {e}", f.display()),
        }
    }
}
