//! The figures drawn from run data: every SVG is well-formed XML with the expected number of
//! data series, a round-off chaotic case is drawn as its ensemble, the index draws one figure
//! per study and the gallery links every figure.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use signorini::engine::fem::MassVariant;
use signorini::engine::schemes::Scheme;
use signorini::harness::reference::exact::run_study;
use signorini::harness::render::figures::layout::{FigureLayout, SeriesKind};
use signorini::harness::render::figures::FigureError;
use signorini::harness::run::norms::Norm;
use signorini::harness::run::{run, Observables, Problem1d, RunConfig};
use signorini::harness::study::sensitivity::{
    CaseSensitivity, EnsembleConfig, Sensitivity, SensitivityClass, Spread, STEP_EPSILON,
};
use signorini::harness::study::{Case, Study, StudyConfig};
use signorini::studies::benchmark;
use signorini::studies::figures::convergence::convergence_figures;
use signorini::studies::figures::from_reports::{
    scheme_figures, stability_figures, write_figures, LONG_HORIZON_NX,
};
use signorini::studies::histories::SchemeHistories;
use signorini::studies::reports_index::{figure_gallery, reports_index};
use signorini::studies::stability::{hard_cases, judge};

/// The Signorini–Dirichlet benchmark of `scenes/bar1d-dirichlet.json`, to `horizon`.
fn dirichlet(horizon: f64) -> Problem1d {
    benchmark::dirichlet(Path::new(env!("CARGO_MANIFEST_DIR")), horizon).unwrap()
}

/// The curves drawn in a figure, over all its charts, as its embedded layout records them
/// (a dashed curve is many `<polyline>`s in the SVG; legend entries with nothing drawn, such
/// as a diverged run's, are not curves).
fn data_lines(svg: &str) -> usize {
    FigureLayout::from_svg(svg)
        .expect("an embedded layout")
        .expect("a layout that parses")
        .charts
        .iter()
        .flat_map(|c| &c.series)
        .filter(|s| s.kind != SeriesKind::Note && s.extent.is_some())
        .count()
}

fn histories(scheme: Scheme, levels: &[usize]) -> SchemeHistories {
    let problem = dirichlet(3.0);
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
                settings: Default::default(),
            };
            runs.push((mass, nx, run(&problem, &config, &mut []).unwrap()));
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

/// Crank–Nicolson with both masses at NX = 10, 20, 40 to T = 3, in two norms.
fn small_study() -> Study {
    let config = StudyConfig {
        levels: vec![10, 20, 40],
        ratio: 10.0,
        horizon: 3.0,
        settings: Default::default(),
    };
    let cases: Vec<Case> = MassVariant::PAPER
        .map(|mass| Case {
            scheme: Scheme::CRANK_NICOLSON,
            mass,
        })
        .to_vec();
    let norms: BTreeSet<Norm> = [Norm::DisplacementLinfH, Norm::EnergyL2].into();
    run_study(&dirichlet(3.0), &cases, &norms, &config).unwrap()
}

/// A sensitivity study of `study`'s cases, by hand: every case reproducible (its members
/// equal to the study's run) except `chaotic`, whose members' errors at each level have the
/// median 4 times the study's, the minimum half the median and the maximum twice it. Every
/// case's rates spread over [0.11, 0.33] with median 0.22.
fn sensitivity_of(study: &Study, chaotic: Case) -> Sensitivity {
    let cases = study
        .cases
        .iter()
        .map(|c| {
            let is_chaotic = c.case == chaotic;
            let factor = if is_chaotic { 4.0 } else { 1.0 };
            let (below, above) = if is_chaotic { (0.5, 2.0) } else { (1.0, 1.0) };
            let errors: BTreeMap<String, Vec<Spread>> = c
                .rates
                .iter()
                .map(|r| {
                    let spreads = r
                        .errors
                        .iter()
                        .map(|&e| Spread {
                            min: below * factor * e,
                            median: factor * e,
                            max: above * factor * e,
                        })
                        .collect();
                    (r.norm.key().to_string(), spreads)
                })
                .collect();
            let rate = Spread {
                min: 0.11,
                median: 0.22,
                max: 0.33,
            };
            let rates = c
                .rates
                .iter()
                .map(|r| (r.norm.key().to_string(), rate))
                .collect();
            let class = if is_chaotic {
                SensitivityClass::Chaotic
            } else {
                SensitivityClass::Reproducible
            };
            let levels = study.config.levels.len();
            CaseSensitivity {
                case: c.case.id(),
                class,
                chaotic: is_chaotic,
                members: 16,
                amplitude: 1e-13,
                step_members: 16,
                step_epsilon: STEP_EPSILON,
                levels: study.config.levels.clone(),
                rates,
                rate_fit_intervals: BTreeMap::new(),
                errors,
                predictability_steps: vec![None; levels],
                separation_growth: vec![None; levels],
                largest_separation: vec![0.0; levels],
                wall_seconds: Vec::new(),
            }
        })
        .collect();
    Sensitivity {
        ensemble: EnsembleConfig::default(),
        config: study.config.clone(),
        cases,
        wall_seconds: 0.0,
    }
}

/// The `points` attribute of an SVG element as pixel coordinates.
fn vertices(node: roxmltree::Node) -> Vec<(f64, f64)> {
    node.attribute("points")
        .unwrap()
        .split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

/// The `<polygon>`s of `svg` with more than the four corners of a legend swatch, as
/// `(fill, vertices)`.
fn bands(svg: &str) -> Vec<(String, Vec<(f64, f64)>)> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    doc.descendants()
        .filter(|n| n.has_tag_name("polygon"))
        .map(|n| (n.attribute("fill").unwrap().to_owned(), vertices(n)))
        .filter(|band| band.1.len() > 4)
        .collect()
}

/// The vertices of the data polyline in `colour` (legend symbols have two).
fn data_line(svg: &str, colour: &str) -> Vec<(f64, f64)> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke") == Some(colour))
        .map(vertices)
        .find(|points| points.len() > 2)
        .unwrap()
}

#[test]
fn convergence_figures_show_both_masses_with_slopes() {
    let study = small_study();
    let figures = convergence_figures(&study, None).unwrap();
    assert_eq!(figures.len(), 2);
    for (name, svg) in &figures {
        assert!(name.starts_with("convergence-crank-nicolson-"));
        assert_eq!(data_lines(svg), 4, "{name}: two masses and their fits");
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
fn a_chaotic_case_is_drawn_as_its_ensemble_median_with_a_band_and_the_others_as_run() {
    let study = small_study();
    let standard = Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
    };
    let sensitivity = sensitivity_of(&study, standard);
    let figures = convergence_figures(&study, Some(&sensitivity)).unwrap();
    let unbanded = convergence_figures(&study, None).unwrap();
    assert_eq!(figures.len(), 2);
    let redistributed_fit = study.cases[1]
        .norm(Norm::DisplacementLinfH)
        .unwrap()
        .fit
        .unwrap()
        .rate;
    let standard_fit = study.cases[0]
        .norm(Norm::DisplacementLinfH)
        .unwrap()
        .fit
        .unwrap()
        .rate;
    for ((name, svg), (_, plain)) in figures.iter().zip(&unbanded) {
        // The standard mass (first colour) only: one band, in its colour.
        let shaded = bands(svg);
        assert_eq!(shaded.len(), 1, "{name}");
        assert_eq!(shaded[0].0, "#0072B2", "{name}");
        assert!(bands(plain).is_empty(), "{name}");
        // The line is the ensemble median: halfway between the band's edges (min = median/2,
        // max = 2 median on the log axis), where the unperturbed run (median/4) is not.
        let band = &shaded[0].1;
        let line = data_line(svg, "#0072B2");
        assert_eq!(band.len(), 2 * line.len(), "{name}");
        for (k, &(x, y)) in line.iter().enumerate() {
            let (upper, lower) = (band[k], band[band.len() - 1 - k]);
            assert_eq!((upper.0, lower.0), (x, x), "{name}");
            assert!(
                (y - 0.5 * (upper.1 + lower.1)).abs() <= 1.0,
                "{name}, level {k}: line at {y}, band {upper:?}..{lower:?}"
            );
        }
        // The legend: the ensemble, its band named, its members' rates with their range and
        // median, and no fit of the unperturbed run; the redistributed mass's fit drawn.
        assert!(
            svg.contains(
                "standard mass: median of 16 round-off runs (chaotic), round-off min–max \
                 shaded; their slopes 0.11 to 0.33 (median 0.22)"
            ),
            "{name}"
        );
        if name.ends_with("u_Linf_H.svg") {
            assert!(!svg.contains(&format!("fit: slope {standard_fit:.2}")));
            assert!(svg.contains(&format!("fit: slope {redistributed_fit:.2}")));
        }
    }
}

#[test]
fn a_sensitivity_study_of_other_levels_or_without_a_norm_is_refused() {
    let study = small_study();
    let standard = Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
    };
    let mut other_levels = sensitivity_of(&study, standard);
    other_levels.config.levels = vec![10, 20, 40, 80];
    match convergence_figures(&study, Some(&other_levels)) {
        Err(FigureError::Inconsistent { what }) => assert!(what.contains("80"), "{what}"),
        other => panic!("{other:?}"),
    }
    let mut without_norm = sensitivity_of(&study, standard);
    without_norm.cases[0].errors.remove("energy_L2");
    match convergence_figures(&study, Some(&without_norm)) {
        Err(FigureError::Inconsistent { what }) => {
            assert!(what.contains("crank-nicolson/standard") && what.contains("energy_L2"))
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn write_figures_reads_the_sensitivity_study_and_refuses_a_malformed_one() {
    let dir = std::env::temp_dir().join(format!("signorini-figures-band-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let study = small_study();
    let rates = serde_json::json!({ "study": study });
    std::fs::write(dir.join("rates.json"), rates.to_string()).unwrap();
    let convergence = dir.join("figures/convergence-crank-nicolson-u_Linf_H.svg");

    // Absent: the figures as before, the input listed as missing.
    let (names, missing) = write_figures(&dir, &dir).unwrap();
    assert!(names.contains(&"convergence-crank-nicolson-u_Linf_H.svg".to_string()));
    assert!(
        missing.iter().any(|m| m.contains("sensitivity.json")),
        "{missing:?}"
    );
    assert!(bands(&std::fs::read_to_string(&convergence).unwrap()).is_empty());

    // Present: the chaotic case gets its band.
    let standard = Case {
        scheme: Scheme::CRANK_NICOLSON,
        mass: MassVariant::Standard,
    };
    let sensitivity = serde_json::to_string(&sensitivity_of(&study, standard)).unwrap();
    std::fs::write(dir.join("sensitivity.json"), sensitivity).unwrap();
    let (_, missing) = write_figures(&dir, &dir).unwrap();
    assert!(
        !missing.iter().any(|m| m.contains("sensitivity.json")),
        "{missing:?}"
    );
    assert_eq!(
        bands(&std::fs::read_to_string(&convergence).unwrap()).len(),
        1
    );

    // Malformed: an error naming the file, not a panic.
    std::fs::write(dir.join("sensitivity.json"), "{\"cases\": 3}").unwrap();
    let err = write_figures(&dir, &dir).unwrap_err().to_string();
    assert!(err.contains("sensitivity.json"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn stability_figures_leave_out_diverged_runs_and_say_so() {
    let hard = hard_cases(Path::new(env!("CARGO_MANIFEST_DIR")), true).unwrap();
    let records: Vec<_> = [
        ("crank-nicolson", MassVariant::Standard),
        ("backward-euler", MassVariant::Standard),
        ("crank-nicolson", MassVariant::Redistributed),
        ("moreau-jean", MassVariant::Standard),
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
    let names: Vec<&str> = figures.iter().map(|f| f.0.as_str()).collect();
    assert_eq!(
        names,
        [
            "stability-standard.svg",
            "stability-redistributed.svg",
            "stability-rivals-standard.svg"
        ],
        "the rivals apart, and no figure without a run"
    );
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
    assert!(standard.contains("crank-nicolson: diverged (not drawn)"));
    assert!(standard.contains(&format!("NX = {}", hard[0].nx)));
    assert_eq!(
        hard[0].nx, LONG_HORIZON_NX,
        "the figures' title says the suite's NX"
    );
    let redistributed = &figures
        .iter()
        .find(|f| f.0 == "stability-redistributed.svg")
        .unwrap()
        .1;
    assert_eq!(data_lines(redistributed), 1);
    let rivals = &figures[2].1;
    assert_eq!(data_lines(rivals), 1);
    assert!(rivals.contains("the rivals, standard mass"));
}

/// The index of the committed reports: each study's headline computed from its data (the count
/// of disagreements is the one `rates.json` lists; the smallest error is the least of
/// `work-precision.json`; the league's series those of `league.json`; each gravity rate named
/// with its scheme), one figure drawn inline per study and no list of figures (the gallery links
/// every figure), and the witness, the finer studies, the league, the cluster plan and the
/// benchmarks linked because they are present.
#[test]
fn the_index_says_what_each_study_found_and_the_gallery_links_every_figure() {
    let reports = Path::new(env!("CARGO_MANIFEST_DIR")).join("reports");
    let index = reports_index(&reports, &[], &[]);
    let gallery = figure_gallery(&reports, &[], &[]).expect("the committed figures");
    let on_disk: Vec<String> = std::fs::read_dir(reports.join("figures"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".svg"))
        .collect();
    assert!(on_disk.len() > 50, "{} figures committed", on_disk.len());
    for n in &on_disk {
        assert!(
            gallery.contains(&format!("(figures/{n})")),
            "{n} not in the gallery"
        );
    }
    let figure_links = index.matches("](figures/").count();
    let drawn = index.matches("![").count();
    assert_eq!(
        figure_links, drawn,
        "the index links figures besides those it draws"
    );
    assert!(drawn <= 8, "{drawn} figures drawn in the index");
    assert!(index.contains("![contact-crank-nicolson](figures/contact-crank-nicolson.svg)"));
    let read = |file: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(reports.join(file)).unwrap()).unwrap()
    };
    let disagreements = read("rates.json")["longer_horizon_rates"]
        .as_array()
        .unwrap()
        .len();
    assert!(
        index.contains(&format!(
            "{disagreements} of the 98 rates (case × norm) are not shown to agree"
        )),
        "{index}"
    );
    let costs = read("work-precision.json");
    let norm = costs["cost_to_target_norm"].as_str().unwrap();
    let smallest = costs["work_precision"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["norm"] == norm)
        .flat_map(|w| w["errors"].as_array().unwrap().iter())
        .map(|e| e.as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert!(
        index.contains(&format!("measured is {smallest:.2e} (")),
        "the smallest error {smallest:.2e} is not the headline's:\n{index}"
    );
    let league = read("league.json");
    let series: usize = league["entries"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["rows"].as_array().unwrap().len())
        .sum();
    assert!(
        index.contains(&format!("{series} refinement series in ")),
        "the league's {series} series are not the headline's:\n{index}"
    );
    let gravity = index
        .lines()
        .find(|l| l.starts_with("The displacement's rate in L∞(0,T;H)"))
        .expect("the gravity headline");
    for label in [
        "Crank–Nicolson: standard",
        "Generalised-α ρ∞ = 0.8 (Chung–Hulbert): standard",
        "Moreau–Jean θ = 1/2, e = 0 (Jean): standard",
        "Laursen–Chawla, energy-conserving: standard",
    ] {
        assert!(gravity.contains(label), "{label} not in: {gravity}");
    }
    for linked in [
        "[gallery.md](gallery.md)",
        "[getfem.md](getfem.md)",
        "[getfem-verify/verify.md](getfem-verify/verify.md)",
        "[fine/README.md](fine/README.md)",
        "[finest/README.md](finest/README.md)",
        "[league.md](league.md)",
        "[cluster/cluster-plan.md](cluster/cluster-plan.md)",
        "[stability.json](stability.json)",
    ] {
        assert!(index.contains(linked), "{linked} not linked");
    }
}

/// The finer studies' indexes are titled after their bars and references, point to the top
/// index and do not repeat its preamble.
#[test]
fn the_finer_studies_indexes_are_titled_after_their_studies() {
    let reports = Path::new(env!("CARGO_MANIFEST_DIR")).join("reports");
    let top = reports_index(&reports, &[], &[]);
    let preamble = top.lines().nth(2).unwrap();
    let mut titles = Vec::new();
    for dir in ["fine", "finest"] {
        let index = reports_index(&reports.join(dir), &[], &[]);
        let title = index.lines().next().unwrap().to_string();
        assert!(
            title.starts_with("# The ") && title.contains(" elements"),
            "{title}"
        );
        assert!(
            !index.contains(preamble),
            "{dir}: the top preamble repeated"
        );
        assert!(index.contains("[top index](../README.md)"), "{index}");
        titles.push(title);
    }
    assert_ne!(titles[0], titles[1]);
    assert_eq!(top.lines().next(), Some("# Reports"));
}

/// A directory with one study (as `reports/finest/`) lists only what it has, and a figure just
/// drawn is listed before it is in the directory.
#[test]
fn the_index_of_a_partial_directory_lists_only_what_it_holds() {
    let reports = Path::new(env!("CARGO_MANIFEST_DIR")).join("reports");
    let dir = std::env::temp_dir().join(format!("signorini-index-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for f in ["elastic-3d.md", "elastic-3d.json"] {
        std::fs::copy(reports.join(f), dir.join(f)).unwrap();
    }
    let drawn = vec!["elastic-3d-contact-crank-nicolson.svg".to_string()];
    let index = reports_index(&dir, &drawn, &[]);
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(index.contains("[elastic-3d.md](elastic-3d.md)"), "{index}");
    assert!(index.contains("(figures/elastic-3d-contact-crank-nicolson.svg)"));
    assert!(index.contains("findings tested"), "{index}");
    for absent in ["tables.md", "stability.md", "getfem.md", "elastic-2d"] {
        assert!(!index.contains(absent), "{absent} listed: {index}");
    }
}

/// The committed indexes and galleries (`reports/`, `reports/fine/`, `reports/finest/`) are
/// what the render step writes from the committed data and figures: regenerated by `signorini
/// figures --out DIR` (`make rejudge`'s last three commands), not edited by hand.
#[test]
fn the_committed_indexes_and_galleries_are_the_rendered_ones() {
    let reports = Path::new(env!("CARGO_MANIFEST_DIR")).join("reports");
    for dir in [
        reports.clone(),
        reports.join("fine"),
        reports.join("finest"),
    ] {
        let committed = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(
            committed("README.md") == reports_index(&dir, &[], &[]),
            "{}/README.md differs from its rendering: run signorini figures --out {0}",
            dir.display()
        );
        assert!(
            Some(committed("gallery.md")) == figure_gallery(&dir, &[], &[]),
            "{}/gallery.md differs from its rendering: run signorini figures --out {0}",
            dir.display()
        );
    }
}
