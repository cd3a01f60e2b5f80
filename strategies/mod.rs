//! Adaptivity strategies, one module each, all driven by the same core through
//! [`crate::adapt::Adaptivity`]. Naming rule: the module is named after the strategy's
//! `--strategy` value (`static_mesh` for `static`, a Rust keyword).

pub mod bisect48;
pub mod remesh;
pub mod simnett;
mod static_mesh;

pub use static_mesh::StaticMesh;

use crate::adapt::Adaptivity;
use crate::scene::STRATEGIES;

/// Why a strategy could not be made.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StrategyError {
    /// The name is not a strategy.
    #[error("unknown strategy `{0}`; valid strategies: {list}", list = STRATEGIES.join(", "))]
    Unknown(String),
}

/// The strategy called `name` (see [`STRATEGIES`]).
pub fn make_strategy(name: &str) -> Result<Box<dyn Adaptivity>, StrategyError> {
    match name {
        "static" => Ok(Box::new(StaticMesh)),
        "bisect48" => Ok(Box::new(bisect48::Bisect48::new())),
        "simnett" => Ok(Box::new(simnett::Simnett::default())),
        "remesh" => Ok(Box::new(remesh::Remesh::new())),
        other => Err(StrategyError::Unknown(other.to_string())),
    }
}
