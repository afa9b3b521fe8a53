//! The render step (`signorini figures`, the last command of `make report`): what a reports
//! directory shows, built from the data files its commands wrote there and from nothing else.
//! Each command writes its own section's data and pages; the pages that gather several
//! sections' data are built here, with the figures and the index:
//!
//! | page | from |
//! |---|---|
//! | `schemes.md` | `rates.json`, `sensitivity.json`, `rates-longer-horizon.json` (`report`), `stability.json` (`stability`, when there) |
//! | `work-precision.md` | `rates.json` with `sensitivity.json` (`report`), `elastic-2d.json`, `elastic-3d.json` (`study`), each where it exists |
//! | `figures/*.svg` | [`crate::studies::figures::from_reports`] |
//! | `README.md`, `gallery.md` | [`crate::studies::reports_index`] |
//!
//! A page whose data is missing is not written (a page already there is kept) and its missing
//! inputs are listed; a data file that is there but does not read is an error.

use std::path::Path;

use serde::de::DeserializeOwned;

use crate::harness::files::artifacts::{read_json, write_atomic};
use crate::harness::files::input::REPORT_DATA;
use crate::harness::study::sensitivity::Sensitivity;
use crate::harness::study::Study;
use crate::studies::cost::{work_precision_page, BoxCosts, WORK_PRECISION_MD};
use crate::studies::elastic_study::files::study_file;
use crate::studies::error::Error;
use crate::studies::figures::from_reports::write_figures;
use crate::studies::reports_index::{figure_gallery, reports_index, FIGURE_GALLERY, REPORTS_INDEX};
use crate::studies::schemes::{self, SCHEMES_MD};
use crate::studies::stability::{StabilityRecord, STABILITY_JSON};
use crate::studies::tables::{
    LongerHorizonFile, RatesFile, LONGER_HORIZON_JSON, RATES_JSON, SENSITIVITY_JSON,
};

/// What the render step wrote, and what it could not.
pub struct Rendered {
    /// The pages written, by file name ([`SCHEMES_MD`], [`WORK_PRECISION_MD`],
    /// [`FIGURE_GALLERY`]).
    pub pages: Vec<&'static str>,
    /// The figures drawn, by file name under `figures/`.
    pub figures: Vec<String>,
    /// The inputs that were missing, each with what it left unwritten.
    pub missing: Vec<String>,
}

/// The cross-section pages of `reports` whose data are there, each with its file name, and
/// the inputs that were missing.
pub struct Pages {
    /// `(file name, markdown)` of each page rendered.
    pub rendered: Vec<(&'static str, String)>,
    /// The inputs that were missing, each with the page it left unwritten.
    pub missing: Vec<String>,
}

/// Renders the reports directory `reports` from its data: writes into `into` (`reports` or
/// where its new files are staged) the cross-section pages ([`cross_section_pages`]), the
/// figures, the gallery of the figures ([`FIGURE_GALLERY`], when there are some) and the index
/// ([`REPORTS_INDEX`], listing the pages and figures just written too).
pub fn render_reports(reports: &Path, into: &Path) -> Result<Rendered, Error> {
    let (figures, mut missing) = write_figures(reports, into)?;
    let pages = cross_section_pages(reports)?;
    for (name, text) in &pages.rendered {
        write_atomic(&into.join(name), text.as_bytes())?;
    }
    missing.extend(pages.missing);
    let mut pages: Vec<&'static str> = pages.rendered.iter().map(|(name, _)| *name).collect();
    if let Some(gallery) = figure_gallery(reports, &figures, &pages) {
        write_atomic(&into.join(FIGURE_GALLERY), gallery.as_bytes())?;
        pages.push(FIGURE_GALLERY);
    }
    let index = reports_index(reports, &figures, &pages);
    write_atomic(&into.join(REPORTS_INDEX), index.as_bytes())?;
    Ok(Rendered {
        pages,
        figures,
        missing,
    })
}

/// The pages that gather several sections' data, `schemes.md` and `work-precision.md`, from the
/// data files under `reports`: each whose data are there.
pub fn cross_section_pages(reports: &Path) -> Result<Pages, Error> {
    let rates: Option<RatesFile> = data(reports, RATES_JSON)?;
    let tables = rates.as_ref().map(|r| &r.study);
    let mut missing = Vec::new();
    let pages = [
        (SCHEMES_MD, schemes_page(reports, tables, &mut missing)?),
        (
            WORK_PRECISION_MD,
            costs_page(reports, tables, &mut missing)?,
        ),
    ];
    Ok(Pages {
        rendered: pages
            .into_iter()
            .filter_map(|(name, page)| page.map(|text| (name, text)))
            .collect(),
        missing,
    })
}

/// The data file `name` under `reports` read into a `T`; `None` when it is absent.
fn data<T: DeserializeOwned>(reports: &Path, name: &str) -> Result<Option<T>, Error> {
    let path = reports.join(name);
    if !path.is_file() {
        return Ok(None);
    }
    Ok(read_json(&path, REPORT_DATA).map(Some)?)
}

/// `schemes.md` ([`schemes::render`]) from the Tables study `tables` (of `rates.json`), its
/// sensitivity and the study over the longer horizon (`report`'s), with the stability suite's
/// records when there are some; `None`, each absent input of `report`'s listed in `missing`,
/// when one is not there.
fn schemes_page(
    reports: &Path,
    tables: Option<&Study>,
    missing: &mut Vec<String>,
) -> Result<Option<String>, Error> {
    let sensitivity: Option<Sensitivity> = data(reports, SENSITIVITY_JSON)?;
    let longer: Option<LongerHorizonFile> = data(reports, LONGER_HORIZON_JSON)?;
    let stability: Option<Vec<StabilityRecord>> = data(reports, STABILITY_JSON)?;
    let (Some(study), Some(sensitivity), Some(longer)) = (tables, &sensitivity, &longer) else {
        for (name, absent) in [
            (RATES_JSON, tables.is_none()),
            (SENSITIVITY_JSON, sensitivity.is_none()),
            (LONGER_HORIZON_JSON, longer.is_none()),
        ] {
            if absent {
                missing.push(format!(
                    "{} ({SCHEMES_MD} not written; run `make report` first)",
                    reports.join(name).display()
                ));
            }
        }
        return Ok(None);
    };
    Ok(Some(schemes::render(
        study,
        sensitivity,
        &longer.study,
        stability.as_deref(),
    )))
}

/// `work-precision.md` ([`work_precision_page`]) from the Tables study `tables` (of
/// `rates.json`, its levels timed with the runs of `sensitivity.json` where it is there) and
/// the 2D and 3D studies (`elastic-2d.json`, `elastic-3d.json`), each where it exists; `None`,
/// listed in `missing`, when none does.
fn costs_page(
    reports: &Path,
    tables: Option<&Study>,
    missing: &mut Vec<String>,
) -> Result<Option<String>, Error> {
    let mut boxes: Vec<BoxCosts> = Vec::new();
    for dimension in [2, 3] {
        boxes.extend(data(reports, &study_file(dimension))?);
    }
    if tables.is_none() && boxes.is_empty() {
        missing.push(format!(
            "{}, {} and {} ({WORK_PRECISION_MD} not written; run `make report` first)",
            reports.join(RATES_JSON).display(),
            study_file(2),
            study_file(3)
        ));
        return Ok(None);
    }
    let sensitivity: Option<Sensitivity> = match tables {
        Some(_) => data(reports, SENSITIVITY_JSON)?,
        None => None,
    };
    Ok(Some(work_precision_page(
        tables,
        sensitivity.as_ref(),
        &boxes,
    )))
}
