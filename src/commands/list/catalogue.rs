//! `signorini list` below the command line: what the harness knows by name (schemes, mass
//! variants, contact treatments, norms) and the scenes found.

use std::path::Path;

use crate::harness::problem::{
    AlphaParameters, MassVariant, PredictorVelocity, Scheme, TREATMENT_LIST,
};
use crate::harness::run::norms::Norm;
use crate::harness::study::scene::{scene_files, Scene};

/// The schemes with their parameters, the mass variants, the contact treatments, the norms
/// and the scenes found in `dir`, as `signorini list` prints them.
pub fn catalogue(dir: &Path) -> String {
    let mut said: Vec<String> = Vec::new();
    let mut out = |line: String| said.push(line);
    out(
        "Schemes (preset name, parameters, the paper's name; [rival]: not in the paper, see \
         docs/src/schemes-and-balances.md):"
            .into(),
    );
    for (name, scheme, label) in Scheme::presets() {
        let params = match scheme {
            Scheme::Newmark { beta, gamma } => format!("Newmark β = {beta}, γ = {gamma}"),
            Scheme::Theta { theta } => format!("θ-method θ = {theta}"),
            Scheme::PaoliSchatzman { beta, restitution } => {
                format!("Paoli–Schatzman β = {beta}, e = {restitution}")
            }
            Scheme::GeneralisedAlpha(AlphaParameters {
                alpha_m,
                alpha_f,
                beta,
                gamma,
            }) => format!("α_m = {alpha_m:.4}, α_f = {alpha_f:.4}, β = {beta:.4}, γ = {gamma:.4}"),
            Scheme::MoreauJean { theta, restitution } => {
                format!("Moreau–Jean θ = {theta}, e = {restitution}")
            }
            Scheme::LaursenChawla {} => "Moreau–Jean θ = 0.5, e = 1, trial gap".to_string(),
            Scheme::ContactStabilisedNewmark { velocity } => match velocity {
                PredictorVelocity::Carried => "Crank–Nicolson after projection, from V^n",
                PredictorVelocity::Projected => {
                    "Crank–Nicolson after projection, from (U^p−U^n)/Δt"
                }
            }
            .to_string(),
        };
        let rival = if Scheme::rival_schemes().contains(&scheme) {
            " [rival]"
        } else {
            ""
        };
        out(format!("  {name:22} {params:44} {label}{rival}"));
    }
    out(
        "  any parameters: newmark(beta=B,gamma=G), theta(theta=T), paoli-schatzman(beta=B,e=E),\n  \
         generalised-alpha(rho_inf=R), hht(alpha=A), \
         generalised-alpha(alpha_m=AM,alpha_f=AF,beta=B,gamma=G), moreau-jean(theta=T,e=E)"
            .into(),
    );
    out("\nMass variants:".into());
    for m in MassVariant::ALL {
        out(format!(
            "  {:25} {:5} {}",
            m.name(),
            m.paper_label(),
            m.description()
        ));
    }
    out("\nContact treatments (E the Young modulus, ρc² for a bar; h the mesh size at the contact):".into());
    for (name, params, description) in TREATMENT_LIST {
        out(format!("  {name:27} {params:22} {description}"));
    }
    out("\nNorms:".into());
    for n in Norm::ALL {
        out(format!("  {:12} {}", n.key(), n.label()));
    }
    out(format!("\nScenes in {}:", dir.display()));
    let files = scene_files(dir);
    if files.is_empty() {
        out("  (none)".into());
    }
    for f in files {
        match Scene::load(&f) {
            Ok(s) => out(format!("  {:40} {}", f.display(), s.description)),
            Err(e) => out(format!("  {:40} INVALID: {e}", f.display())),
        }
    }
    said.join("\n")
}
