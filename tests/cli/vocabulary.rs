//! The verdict words: `docs/src/vocabulary.md` carries the table of `harness::vocabulary`
//! (every word and threshold of the module, nothing else), and the deciding code that lives
//! outside the module decides with the module's thresholds.

use std::path::PathBuf;

use signorini::harness::vocabulary;

const BEGIN: &str = "<!-- vocabulary: the rows below are vocabulary::table() -->\n";
const END: &str = "<!-- vocabulary: end -->";

fn page() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/src/vocabulary.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The page with its table block replaced by `table`.
fn with_table(page: &str, table: &str) -> String {
    let start = page.find(BEGIN).expect("the page marks its table") + BEGIN.len();
    let end = page.find(END).expect("the page ends its table");
    format!("{}{table}{}", &page[..start], &page[end..])
}

/// The page's table is the module's: a word or threshold the module has and the page lacks, or
/// the reverse, fails. On a difference the page as it should be is written to
/// `target/vocabulary.md`.
#[test]
fn the_vocabulary_page_carries_the_modules_table() {
    let page = page();
    let expected = with_table(&page, &vocabulary::table());
    if page != expected {
        let out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/vocabulary.md");
        std::fs::write(&out, &expected).unwrap();
        panic!(
            "docs/src/vocabulary.md differs from vocabulary::table(); the page as it should be \
             is in {}",
            out.display()
        );
    }
    for w in vocabulary::words() {
        assert!(page.contains(&format!("| **{}** |", w.word)), "{}", w.word);
        let threshold = vocabulary::table_cell(&w.threshold);
        assert!(page.contains(&threshold), "{threshold}");
    }
}

/// The thresholds of deciding code outside the module are the module's.
#[test]
fn the_deciding_code_uses_the_vocabularys_thresholds() {
    use signorini::studies::tables::agreement::PAPER_AGREEMENT;
    assert_eq!(PAPER_AGREEMENT, vocabulary::AGREES_WITHIN);
}
