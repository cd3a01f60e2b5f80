//! The stability suite at small sizes: every hard case of `docs/stability.md` with its pass
//! criterion asserted, for every built strategy, plus bracketing checks of the largest stable
//! step. The full-size report is `adaptcloth stability`.
use adaptcloth::study::stability::{self, CaseSizes, Search};

#[test]
fn hard_cases_pass_for_every_built_strategy() {
    let strategies = stability::built_strategies();
    assert!(strategies.contains(&"static"));
    for strategy in strategies {
        for c in stability::hard_cases(strategy, &CaseSizes::QUICK) {
            assert!(
                c.passed,
                "{} / {} / {}: {} -- measured: {}",
                c.case, c.strategy, c.integrator, c.criterion, c.measured
            );
        }
    }
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
