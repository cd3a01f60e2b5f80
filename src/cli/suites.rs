//! `integrators` and `stability`: the suites that write `docs/integrators.md` and
//! `docs/stability.md`.

use super::{check_report_path, read_input, write_report_file, CliError};
use crate::strategies::strategy_named;
use crate::study::integrators;
use crate::study::stability::{self, CaseSizes, Search, REPORT_SEARCH};
use std::path::{Path, PathBuf};

/// `adaptcloth integrators`: seed 004's tables and the convergence orders, optionally written
/// into `docs` between its markers.
pub fn integrators(write_docs: bool, docs: &Path) -> Result<(), CliError> {
    // The document is read before the experiments run, so a wrong path costs nothing.
    let text = match write_docs {
        true => Some(read_input(docs).map_err(|e| {
            CliError::Input(format!(
                "--docs {e} (expected the document to update; the default, \
                 docs/integrators.md, is found from the repository's root)"
            ))
        })?),
        false => None,
    };
    let table = integrators::report();
    crate::console::stdout(format_args!("{table}"));
    let Some(text) = text else {
        return Ok(());
    };
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

/// `adaptcloth stability`: the stability suite, its report written to `out` (default
/// `docs/stability.md`, or `out/stability-quick.md` with `quick`, so a quick look never replaces
/// the report in `docs/`); with `strategy`, that strategy alone, reported by default to
/// `out/stability[-quick]-STRATEGY.md`. An unknown strategy or an unwritable `out` is refused
/// (exit 2) before anything runs. Fails (exit 1) when a hard case failed, after writing the report.
pub fn stability(out: Option<&Path>, quick: bool, strategy: Option<&str>) -> Result<(), CliError> {
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
    let strategies = match strategy {
        Some(name) => vec![
            strategy_named(name)
                .map_err(|e| CliError::Input(format!("--strategy {name}: {e}")))?
                .name,
        ],
        None => stability::built_strategies(),
    };
    let default_out = match (strategy, quick) {
        (None, false) => PathBuf::from("docs/stability.md"),
        (None, true) => PathBuf::from("out/stability-quick.md"),
        (Some(s), false) => PathBuf::from(format!("out/stability-{s}.md")),
        (Some(s), true) => PathBuf::from(format!("out/stability-quick-{s}.md")),
    };
    let out = out.unwrap_or(&default_out);
    check_report_path(out)?;
    let suite = stability::report(&search, &sizes, &strategies, |s| {
        crate::note!("adaptcloth stability: {s}")
    });
    write_report_file(out, &suite.markdown)?;
    if suite.failed > 0 {
        return Err(CliError::Failed(format!(
            "{} stability case(s) failed (see {})",
            suite.failed,
            out.display()
        )));
    }
    Ok(())
}
