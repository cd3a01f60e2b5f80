//! Adaptivity strategies, one module each, all driven by the same core through
//! [`crate::adapt::Adaptivity`]. Naming rule: the module is named after the strategy's
//! `--strategy` value (`static_mesh` for `static`, a Rust keyword).
//!
//! [`STRATEGIES`] is the one registry: each strategy's name, a one-line description, the
//! strategy-specific adaptivity parameters it reads and its constructor. Adding a strategy is
//! adding its module and its line there; scenes, the CLI, comparisons and benches ask the
//! registry ([`strategy_named`], [`strategy_names`], [`make_strategy`]).

pub mod bisect48;
pub mod remesh;
pub mod simnett;
mod static_mesh;

pub use static_mesh::StaticMesh;

use crate::adapt::Adaptivity;

/// One registered strategy.
#[derive(Clone, Copy, Debug)]
pub struct StrategyInfo {
    /// The name given to `--strategy` and `[adaptivity] strategy`.
    pub name: &'static str,
    /// One line saying what the strategy does.
    pub description: &'static str,
    /// Whether the strategy ever changes the mesh. `false` (the static baseline) means no
    /// adaptivity parameter has any effect on it.
    pub edits_mesh: bool,
    /// The strategy-specific adaptivity parameters it reads, by name: fields of
    /// [`crate::adapt::AdaptParams`], which are also the scene's `[adaptivity]` keys. The shared
    /// criteria, the evaluation interval and the transfer options apply to every strategy that
    /// edits the mesh and are not listed.
    pub options: &'static [&'static str],
    /// A new strategy with no history.
    pub make: fn() -> Box<dyn Adaptivity>,
}

/// Every strategy, by name, in the order comparisons and reports list them.
pub const STRATEGIES: &[StrategyInfo] = &[
    StrategyInfo {
        name: "static",
        description: "never changes the mesh: the baseline at fixed resolutions",
        edits_mesh: false,
        options: &[],
        make: || Box::new(StaticMesh),
    },
    StrategyInfo {
        name: "remesh",
        description: "local remeshing: regions of selected edges removed and re-meshed in rest \
                      space, finer or coarser",
        edits_mesh: true,
        options: &[
            "curvature_exponent",
            "density_refine",
            "density_simplify",
            "remesh_min_angle",
        ],
        make: || Box::new(remesh::Remesh::new()),
    },
    StrategyInfo {
        name: "simnett",
        description: "edge-based 1-to-4 subdivision with temporary children (Simnett et al. 2009)",
        edits_mesh: true,
        options: &["max_depth", "depth_factor", "force_completion"],
        make: || Box::new(simnett::Simnett::default()),
    },
    StrategyInfo {
        name: "bisect48",
        description: "newest-vertex bisection on the 4-8 mesh (Velho & Zorin 2001)",
        edits_mesh: true,
        options: &["curvature_exponent", "max_depth"],
        make: || Box::new(bisect48::Bisect48::new()),
    },
];

/// The names of [`STRATEGIES`], in registry order.
const NAMES: [&str; STRATEGIES.len()] = {
    let mut names = [""; STRATEGIES.len()];
    let mut i = 0;
    while i < STRATEGIES.len() {
        names[i] = STRATEGIES[i].name;
        i += 1;
    }
    names
};

/// The names of every strategy, in registry order (`static, remesh, simnett, bisect48`).
pub fn strategy_names() -> &'static [&'static str] {
    &NAMES
}

/// Why a strategy could not be found.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StrategyError {
    /// The name is not a strategy.
    #[error("unknown strategy `{0}`; valid strategies: {list}", list = NAMES.join(", "))]
    Unknown(String),
}

/// The registry entry of the strategy called `name`.
pub fn strategy_named(name: &str) -> Result<&'static StrategyInfo, StrategyError> {
    STRATEGIES
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| StrategyError::Unknown(name.to_string()))
}

/// True when the strategy called `name` edits the mesh (false for `static` and unknown names).
pub fn edits_mesh(name: &str) -> bool {
    strategy_named(name).is_ok_and(|s| s.edits_mesh)
}

/// A new strategy called `name` (see [`STRATEGIES`]).
pub fn make_strategy(name: &str) -> Result<Box<dyn Adaptivity>, StrategyError> {
    strategy_named(name).map(|s| (s.make)())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registered_strategy_builds_and_answers_to_its_name() {
        for info in STRATEGIES {
            assert_eq!((info.make)().name(), info.name);
            assert_eq!(make_strategy(info.name).map(|s| s.name()), Ok(info.name));
            assert!(!info.description.is_empty());
        }
        assert_eq!(
            strategy_names(),
            ["static", "remesh", "simnett", "bisect48"]
        );
    }

    #[test]
    fn an_unknown_name_lists_the_valid_ones() {
        let e = strategy_named("quadtree").unwrap_err();
        assert_eq!(
            e.to_string(),
            "unknown strategy `quadtree`; valid strategies: static, remesh, simnett, bisect48"
        );
    }
}
