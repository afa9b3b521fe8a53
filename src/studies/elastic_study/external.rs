//! Another code's runs, as the harness measured them ([`crate::harness::external::verify`]),
//! judged and rendered: the note's findings judged on the series that declare their scheme and
//! mass, each rate's interval widened by the fine-mesh reference's rate-bias bound of its case
//! (against an exact solution, a bar's, nothing is judged), and `verify.md`, the harness's
//! tables followed by the findings.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use super::findings::{findings_of_cases, Finding};
use super::report::findings_table;
use crate::harness::external::report::render as render_tables;
use crate::harness::external::verify::declared_cases;
use crate::harness::external::verify::own_mesh::own_mesh_caveats;
use crate::harness::external::{Measured, Verification};

/// What verify.json adds to the harness's measurements: the note's findings.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Judgement {
    /// The note's findings judged on the series that declare a scheme and a mass (each
    /// `(scheme, mass)` once; empty when none do), against a fine-mesh reference; absent
    /// against an exact solution.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub findings: Option<Vec<Finding>>,
    /// What the findings on series measured on their own mesh rest on
    /// ([`own_mesh_caveats`]); empty when none is.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub caveats: Vec<String>,
}

/// A verification with the note's findings judged on it (`verify.json`).
pub type JudgedVerification = Verification<Judgement>;

/// The verification `measured` with the note's findings judged on it when its reference bounds
/// its rates' bias (a fine-mesh reference).
pub fn judged(measured: Measured) -> JudgedVerification {
    let findings = measured.rate_bias().map(|bias| {
        let cases = declared_cases(&measured.verification.series);
        if cases.is_empty() {
            Vec::new()
        } else {
            findings_of_cases(&cases, &bias)
        }
    });
    let caveats = own_mesh_caveats(&measured.verification.series);
    measured
        .verification
        .judged(Judgement { findings, caveats })
}

/// The markdown of a verification: the harness's tables, then the note's findings when some
/// were judged.
pub fn render(v: &JudgedVerification) -> String {
    let mut out = render_tables(v);
    if let Some(findings) = v.judgement.findings.as_ref().filter(|f| !f.is_empty()) {
        let _ = writeln!(
            out,
            "\n## The note's findings, on the series that declare a scheme and a mass\n\n{}",
            findings_table(findings)
        );
        out.push_str(&caveats_list(&v.judgement.caveats));
    }
    out
}

/// The caveats of findings judged on series on their own mesh, as a list under its heading;
/// empty when there are none.
pub fn caveats_list(caveats: &[String]) -> String {
    if caveats.is_empty() {
        return String::new();
    }
    let items: Vec<String> = caveats.iter().map(|c| format!("- {c}")).collect();
    format!(
        "What these findings rest on, for the series on their own mesh:\n\n{}\n",
        items.join("\n")
    )
}
