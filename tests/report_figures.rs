//! The figures drawn from run data: every SVG is well-formed XML with the expected number of
//! data series, and the index links every figure.

use std::collections::BTreeSet;

use signorini::fem::MassVariant;
use signorini::figures::from_reports::{
    convergence_figures, reports_index, scheme_figures, stability_figures, SchemeHistories,
};
use signorini::norms::Norm;
use signorini::run::{run, Observables, Problem1d, RunConfig};
use signorini::schemes::Scheme;
use signorini::stability::{hard_cases, judge};
use signorini::study::{run_study, Case, StudyConfig};

/// Data polylines: plotters draws each line series as one `<polyline>` with a stroke width of
/// at least 2 and more than two points (legend swatches have exactly two).
fn data_lines(svg: &str) -> usize {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .filter(|n| {
            let wide = n
                .attribute("stroke-width")
                .and_then(|w| w.parse::<f64>().ok())
                .is_some_and(|w| w >= 2.0);
            let points = n
                .attribute("points")
                .map_or(0, |p| p.split_whitespace().count());
            wide && points > 2
        })
        .count()
}

fn histories(scheme: Scheme, levels: &[usize]) -> SchemeHistories {
    let problem = Problem1d::signorini_dirichlet(3.0);
    let mut runs = Vec::new();
    for mass in MassVariant::PAPER {
        for &nx in levels {
            let config = RunConfig {
                nx,
                ratio: 10.0,
                scheme,
                mass,
                observables: Observables {
                    contact_history: true,
                    energy_history: true,
                    ..Observables::default()
                },
            };
            runs.push((mass, nx, run(&problem, &config).unwrap()));
        }
    }
    SchemeHistories {
        scheme: scheme.name(),
        label: scheme.label(),
        runs,
    }
}

#[test]
fn contact_and_energy_figures_have_one_curve_per_run_and_the_exact_one() {
    let figures = scheme_figures(&histories(Scheme::CRANK_NICOLSON, &[10, 20])).unwrap();
    let names: Vec<&str> = figures.iter().map(|f| f.0.as_str()).collect();
    assert_eq!(
        names,
        ["contact-crank-nicolson.svg", "energy-crank-nicolson.svg"]
    );
    // 2 panels × 2 charts (u, λ) × (2 runs + exact).
    assert_eq!(data_lines(&figures[0].1), 12);
    // 2 panels × (2 runs + exact).
    assert_eq!(data_lines(&figures[1].1), 6);
}

#[test]
fn convergence_figures_show_both_masses_with_slopes() {
    let config = StudyConfig {
        levels: vec![10, 20, 40],
        ratio: 10.0,
        horizon: 3.0,
    };
    let cases: Vec<Case> = MassVariant::PAPER
        .map(|mass| Case {
            scheme: Scheme::CRANK_NICOLSON,
            mass,
        })
        .to_vec();
    let norms: BTreeSet<Norm> = [Norm::DisplacementLinfH, Norm::EnergyL2].into();
    let study = run_study(
        &Problem1d::signorini_dirichlet(3.0),
        &cases,
        &norms,
        &config,
    )
    .unwrap();
    let figures = convergence_figures(&study).unwrap();
    assert_eq!(figures.len(), 2);
    for (name, svg) in &figures {
        assert!(name.starts_with("convergence-crank-nicolson-"));
        assert_eq!(data_lines(svg), 2, "{name}");
        let slope = study.cases[1]
            .norm(Norm::DisplacementLinfH)
            .unwrap()
            .fit
            .unwrap()
            .rate;
        if name.ends_with("u_Linf_H.svg") {
            assert!(svg.contains(&format!("slope {slope:.2}")), "{name}");
        }
    }
}

#[test]
fn stability_figures_leave_out_diverged_runs_and_say_so() {
    let hard = hard_cases(true);
    let records: Vec<_> = [
        ("crank-nicolson", MassVariant::Standard),
        ("backward-euler", MassVariant::Standard),
        ("crank-nicolson", MassVariant::Redistributed),
    ]
    .iter()
    .map(|(s, m)| {
        judge(
            &hard[0],
            Case {
                scheme: s.parse().unwrap(),
                mass: *m,
            },
        )
        .unwrap()
    })
    .collect();
    let figures = stability_figures(&records).unwrap();
    assert_eq!(figures.len(), 2);
    let standard = &figures
        .iter()
        .find(|f| f.0 == "stability-standard.svg")
        .unwrap()
        .1;
    assert_eq!(
        data_lines(standard),
        1,
        "the diverged Crank–Nicolson run is not drawn"
    );
    assert!(standard.contains("not drawn: crank-nicolson"));
    let redistributed = &figures
        .iter()
        .find(|f| f.0 == "stability-redistributed.svg")
        .unwrap()
        .1;
    assert_eq!(data_lines(redistributed), 1);
}

#[test]
fn the_index_links_every_figure_with_a_sentence() {
    let names: Vec<String> = [
        "contact-crank-nicolson.svg",
        "energy-crank-nicolson.svg",
        "convergence-crank-nicolson-u_Linf_H.svg",
        "gravity-points-standard.svg",
        "work-precision.svg",
        "stability-standard.svg",
    ]
    .map(String::from)
    .to_vec();
    let index = reports_index(&names);
    for n in &names {
        assert!(index.contains(&format!("(figures/{n})")), "{n} not linked");
    }
    assert!(index.contains("[tables.md](tables.md)"));
}
