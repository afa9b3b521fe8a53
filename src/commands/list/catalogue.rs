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
    let mut said: Vec<String> = vec![
        "Schemes (preset name, parameters, the paper's name; [rival]: not in the paper, see \
         docs/src/schemes-and-balances.md):"
            .into(),
    ];
    let mut rows = Vec::new();
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
        rows.push(vec![name.to_string(), params, format!("{label}{rival}")]);
    }
    said.extend(aligned(&rows));
    said.push(
        "  any parameters: newmark(beta=B,gamma=G), theta(theta=T), paoli-schatzman(beta=B,e=E),\n  \
         generalised-alpha(rho_inf=R), hht(alpha=A), \
         generalised-alpha(alpha_m=AM,alpha_f=AF,beta=B,gamma=G), moreau-jean(theta=T,e=E)"
            .into(),
    );
    said.push("\nMass variants:".into());
    let masses: Vec<Vec<String>> = MassVariant::ALL
        .iter()
        .map(|m| {
            vec![
                m.name().to_string(),
                m.paper_label().to_string(),
                m.description().to_string(),
            ]
        })
        .collect();
    said.extend(aligned(&masses));
    said.push(
        "\nContact treatments (E the Young modulus, ρc² for a bar; h the mesh size at the contact):"
            .into(),
    );
    let treatments: Vec<Vec<String>> = TREATMENT_LIST
        .iter()
        .map(|(name, params, description)| {
            vec![
                name.to_string(),
                params.to_string(),
                description.to_string(),
            ]
        })
        .collect();
    said.extend(aligned(&treatments));
    said.push("\nNorms:".into());
    let norms: Vec<Vec<String>> = Norm::ALL
        .iter()
        .map(|n| vec![n.key().to_string(), n.label().to_string()])
        .collect();
    said.extend(aligned(&norms));
    said.push(format!("\nScenes in {}:", dir.display()));
    let files = scene_files(dir);
    if files.is_empty() {
        said.push("  (none)".into());
    }
    let scenes: Vec<Vec<String>> = files
        .iter()
        .map(|f| {
            let what = match Scene::load(f) {
                Ok(s) => s.description,
                Err(e) => format!("INVALID: {e}"),
            };
            vec![f.display().to_string(), what]
        })
        .collect();
    said.extend(aligned(&scenes));
    said.join("\n")
}

/// `rows` as lines indented by two spaces, each column but the last padded to its widest cell
/// (in characters) and two spaces apart.
fn aligned(rows: &[Vec<String>]) -> Vec<String> {
    let columns = rows.iter().map(Vec::len).max().unwrap_or(0);
    let widths: Vec<usize> = (0..columns)
        .map(|c| {
            rows.iter()
                .filter_map(|r| r.get(c))
                .map(|cell| cell.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    rows.iter()
        .map(|row| {
            let mut line = String::from(" ");
            for (c, cell) in row.iter().enumerate() {
                line.push(' ');
                line.push_str(cell);
                if c + 1 < row.len() {
                    let pad = widths[c] - cell.chars().count() + 1;
                    line.extend(std::iter::repeat_n(' ', pad));
                }
            }
            line
        })
        .collect()
}
