//! Renders SVG figures to PNG with resvg, as the figure test lays them out (the system fonts,
//! `sans-serif` resolved to DejaVu Sans when it is installed):
//!
//! ```sh
//! cargo run --example figure_png -- reports/figures/work-precision.svg out.png [more pairs]
//! ```
//!
//! It made the before/after pictures of `docs/src/figures/before-after/`.

use std::process::ExitCode;
use std::sync::Arc;

use resvg::{tiny_skia, usvg};

/// Renders the SVG file `input` to the PNG file `output` at its own size.
fn render(fonts: &Arc<usvg::fontdb::Database>, input: &str, output: &str) -> Result<(), String> {
    let svg = std::fs::read(input).map_err(|e| format!("{input}: {e}"))?;
    let options = usvg::Options {
        fontdb: fonts.clone(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_data(&svg, &options).map_err(|e| format!("{input}: {e}"))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| format!("{input}: empty canvas"))?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap
        .save_png(output)
        .map_err(|e| format!("{output}: {e}"))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() || args.len() % 2 != 0 {
        eprintln!("usage: figure_png IN.svg OUT.png [IN.svg OUT.png …]");
        return ExitCode::from(2);
    }
    let mut db = usvg::fontdb::Database::new();
    db.load_system_fonts();
    db.set_sans_serif_family("DejaVu Sans");
    let fonts = Arc::new(db);
    for pair in args.chunks(2) {
        if let Err(e) = render(&fonts, &pair[0], &pair[1]) {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}
