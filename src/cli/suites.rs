//! `integrators` and `stability`: the suites that write `docs/integrators.md` and
//! `docs/stability.md`.

use super::{read_input, write_report_file, CliError};
use crate::study::integrators;
use crate::study::stability::{self, CaseSizes, Search, REPORT_SEARCH};
use std::path::Path;

/// `adaptcloth integrators`: seed 004's tables and the convergence orders, optionally written
/// into `docs` between its markers.
pub fn integrators(write_docs: bool, docs: &Path) -> Result<(), CliError> {
    let table = integrators::report();
    print!("{table}");
    if !write_docs {
        return Ok(());
    }
    let text = read_input(docs)?;
    let new = integrators::replace_generated(&text, &table).ok_or_else(|| {
        CliError::Input(format!(
            "{} lacks the markers {} ... {}",
            docs.display(),
            integrators::TABLE_BEGIN,
            integrators::TABLE_END
        ))
    })?;
    write_report_file(docs, &new)
}

/// `adaptcloth stability`: the stability suite, its report written to `out`.
pub fn stability(out: &Path, quick: bool) -> Result<(), CliError> {
    let (search, sizes) = if quick {
        let search = Search {
            resolution: 5,
            duration: 0.1,
            iterations: 4,
            ..REPORT_SEARCH
        };
        (search, CaseSizes::QUICK)
    } else {
        (REPORT_SEARCH, CaseSizes::REPORT)
    };
    let md = stability::report(&search, &sizes, |s| eprintln!("adaptcloth stability: {s}"));
    write_report_file(out, &md)
}
