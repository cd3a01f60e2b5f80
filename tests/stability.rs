//! The stability suite at small sizes: every hard case of `docs/stability.md` with its pass
//! criterion asserted for every built strategy (the few known failures listed with their
//! cause), plus bracketing checks of the largest stable step. The full-size report is `adaptcloth stability`.
use adaptcloth::study::stability::{self, CaseSizes, Search};

/// Hard cases still failing, each with its cause (measured; docs/stability.md):
/// `(case, strategy, integrator, why)`. Every other case must pass for every built strategy, and a listed case
/// that starts passing fails this test until it is removed from the list.
const KNOWN_FAILURES: [(&str, &str, &str, &str); 2] = [
    (
        "cloth draped over a plate",
        "remesh",
        "rk4",
        REMESH_OVER_THE_PLATE,
    ),
    (
        "cloth draped over a plate",
        "remesh",
        "implicit_euler",
        REMESH_OVER_THE_PLATE,
    ),
];

/// Why `remesh` fails the draped plate since the face penalty (2026-11-30; measured at the
/// quick size, 9x9 for 0.2 s: rises of 7.8e-3 J under implicit Euler and 8.0e-3 J under RK4,
/// against a tolerance of 5.9e-3 J; the cause measured under implicit Euler).
const REMESH_OVER_THE_PLATE: &str = "under implicit Euler one adaptation event over the plate's edge adds 2.0e-2 J to the total energy (its edits plus the face pass after them: the stretch energy jumps); skipping that face pass, the steps add more (5.7e-2 J); with the face holds instead of the penalty the case passed (docs/model-notes.md, \"Face contact as a penalty\")";

/// The hard cases pass for every built strategy, but for the [`KNOWN_FAILURES`].
#[test]
fn hard_cases_pass_for_every_built_strategy() {
    let strategies = stability::built_strategies();
    assert!(strategies.contains(&"static"));
    let mut unexpected = Vec::new();
    let mut known_seen = Vec::new();
    let mut ran = 0;
    for strategy in strategies {
        for c in stability::hard_cases(strategy, &CaseSizes::QUICK) {
            ran += 1;
            let known = KNOWN_FAILURES
                .iter()
                .find(|k| (k.0, k.1, k.2) == (c.case, c.strategy.as_str(), c.integrator.as_str()));
            match (c.passed, known) {
                (true, None) => {}
                (true, Some(k)) => unexpected.push(format!(
                    "{} / {} / {} now passes: remove it from KNOWN_FAILURES",
                    k.0, k.1, k.2
                )),
                (false, Some(k)) => {
                    known_seen.push(format!("{} / {} / {}: {}", k.0, k.1, k.2, k.3))
                }
                (false, None) => unexpected.push(format!(
                    "{} / {} / {}: {} -- measured: {}",
                    c.case, c.strategy, c.integrator, c.criterion, c.measured
                )),
            }
        }
    }
    for line in &known_seen {
        eprintln!("known failure (reported in docs/stability.md): {line}");
    }
    assert!(ran > 0);
    assert!(unexpected.is_empty(), "{}", unexpected.join("\n"));
}

#[test]
fn explicit_schemes_break_near_the_explicit_limit_and_implicit_euler_does_not() {
    let search = Search {
        resolution: 5,
        duration: 0.1,
        range: (0.01, 16.0),
        iterations: 3,
    };
    let rk4 = stability::largest_stable("rk4", "static", 1e7, &search);
    assert!(
        rk4.multiple > 0.01 && rk4.unstable_at <= 1.0,
        "rk4 stable up to {} and unstable at {}",
        rk4.multiple,
        rk4.unstable_at
    );
    let implicit = stability::largest_stable("implicit_euler", "static", 1e7, &search);
    assert!(
        implicit.multiple >= 4.0,
        "implicit Euler only to {}",
        implicit.multiple
    );
}
