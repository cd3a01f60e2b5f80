//! The adaptivity parameters (MODEL.md §6-§8): the shared criteria, the transfer options, the
//! evaluation interval and the strategy-specific settings. A plain struct with documented
//! defaults (the scene's defaults); the scene converts its `[adaptivity]` section into it. Field
//! names are the scene's keys; which strategies read the strategy-specific ones is said by the
//! strategy registry (`crate::strategies::STRATEGIES`).

use crate::math::Real;

/// Which criteria select the edges to refine and simplify.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Criteria {
    /// The source's criteria (MODEL.md §7): compression, collision, area-scaled curvature.
    #[default]
    Source,
    /// The sizing field (MODEL.md §10.1, [`super::sizing`]): a target rest length per edge from
    /// curvature, velocity gradient, compression and obstacle curvature.
    Sizing,
}

/// Every adaptivity parameter. Shared by every strategy that edits the mesh unless marked
/// otherwise.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptParams {
    /// Refuse an edit whose new faces or edges would cross the cloth (set when the scene's
    /// self-collision is on, `collision.self`). Default off.
    pub refuse_crossings: bool,
    /// Restore the linear momentum of the touched vertices by a uniform velocity correction.
    /// Default on.
    pub restore_momentum: bool,
    /// Restore the kinetic energy an edit loses by the momentum-neutral correction of MODEL.md
    /// §8.4 rule 6 ([`super::restore_kinetic_energy`]). Default off.
    pub restore_energy: bool,
    /// Which criteria select edges. Default [`Criteria::Source`].
    pub criteria: Criteria,
    /// Sizing field: tolerated normal change across an edge, for the curvature and obstacle terms
    /// (rad). Default 0.25.
    pub size_angle: Real,
    /// Sizing field: tolerated velocity difference across an edge (m/s). Default 0.5.
    pub size_velocity: Real,
    /// Sizing field: tolerated compressive strain before buckling is anticipated
    /// (dimensionless). Default 0.02.
    pub size_compression: Real,
    /// Sizing field: distance (m) within which an obstacle's curvature sizes the cloth, grown by
    /// the distance the fastest vertex travels in one `interval`. Default 0.05.
    pub size_proximity: Real,
    /// Compression criterion `c` (dimensionless): refine when `L / L_rest < c`. Default 0.70.
    pub compression_c: Real,
    /// Curvature: refine when the cosine between end normals is below this. Default 0.97.
    pub cos_refine: Real,
    /// Curvature: simplify when the cosine is above this. Default 0.999995.
    pub cos_simplify: Real,
    /// No refinement of an edge shorter than this at rest (m). Default 0.08.
    pub l_min: Real,
    /// No simplification above this rest length (m). Default 0.25.
    pub l_max: Real,
    /// The shortest rest edge a strategy may create (m); 0 leaves `l_min` and `max_depth` in
    /// charge ([`AdaptParams::refine_min_length`], [`AdaptParams::depth_limit`]). Default 0.
    pub h_min: Real,
    /// Smoothing (4.19): refine a neighbour j of a selected edge i when `L_i / L_j < c2`
    /// (dimensionless). Default 0.75.
    pub c2: Real,
    /// Hysteresis: no simplification until this long after refinement (s). Default 0.1.
    pub t_simplify: Real,
    /// Collision criterion: an edge meeting an obstacle is not refined when the mean normal of
    /// its faces and the obstacle normal have an absolute cosine at least this (flat contact).
    /// Default 0.97.
    pub flat_contact_cos: Real,
    /// Rounds per adaptation pass: the strategy is called again while its last round added
    /// vertices, at most this many times, so one pass can refine several levels (with the sizing
    /// field, down to the target sizes). Default 1 (the source: one round).
    pub rounds: u32,
    /// Simulated time between adaptation passes (s); 0 adapts after every step. Default 0.01.
    pub interval: Real,
    /// Strategy-specific (`remesh`, `bisect48`: the strategies using the area-scaled curvature
    /// limit): exponent of `theta_refine = theta_max (A_max / A_e)^exponent`. Default 0.5.
    pub curvature_exponent: Real,
    /// Strategy-specific (`remesh`): density factor scale when refining (4.20-4.22).
    /// Default 1.01.
    pub density_refine: Real,
    /// Strategy-specific (`remesh`): density factor scale when simplifying. Default 0.35.
    pub density_simplify: Real,
    /// Strategy-specific (`remesh`): minimum angle the hole mesher keeps away from the hole
    /// border (degrees). Default 25.
    pub remesh_min_angle: Real,
    /// Strategy-specific (`simnett`, `bisect48`): maximum subdivision depth in 1-to-4 levels
    /// (`bisect48` allows twice as many bisection levels). Default 3.
    pub max_depth: u32,
    /// Strategy-specific (`simnett`): cosine-limit factor per depth level. Default 0.95.
    pub depth_factor: Real,
    /// Strategy-specific (`simnett`): complete a blocking parent triangle so a selected edge can
    /// split, instead of waiting (the source's rule). Default off.
    pub force_completion: bool,
}

impl Default for AdaptParams {
    fn default() -> Self {
        AdaptParams {
            refuse_crossings: false,
            restore_momentum: true,
            restore_energy: false,
            criteria: Criteria::Source,
            size_angle: 0.25,
            size_velocity: 0.5,
            size_compression: 0.02,
            size_proximity: 0.05,
            compression_c: 0.70,
            cos_refine: 0.97,
            cos_simplify: 0.999995,
            l_min: 0.08,
            l_max: 0.25,
            h_min: 0.0,
            c2: 0.75,
            t_simplify: 0.1,
            flat_contact_cos: 0.97,
            rounds: 1,
            interval: 0.01,
            curvature_exponent: 0.5,
            density_refine: 1.01,
            density_simplify: 0.35,
            remesh_min_angle: 25.0,
            max_depth: 3,
            depth_factor: 0.95,
            force_completion: false,
        }
    }
}

impl AdaptParams {
    /// The shortest rest edge (m) the criteria may select for refinement: `2 h_min` when `h_min`
    /// is set (so the halves are at least `h_min`), else `l_min`.
    pub fn refine_min_length(&self) -> Real {
        if self.h_min > 0.0 {
            2.0 * self.h_min
        } else {
            self.l_min
        }
    }

    /// The subdivision depth limit in 1-to-4 levels for a mesh whose longest initial rest edge is
    /// `longest` (m): with `h_min` set, the levels that halving `longest` takes to reach `h_min`
    /// (so the depth never binds before the length does), else `max_depth`.
    pub fn depth_limit(&self, longest: Real) -> u32 {
        if self.h_min > 0.0 && longest > self.h_min {
            (longest / self.h_min).log2().ceil().min(30.0) as u32
        } else if self.h_min > 0.0 {
            0
        } else {
            self.max_depth
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn h_min_replaces_the_length_and_depth_limits() {
        let p = AdaptParams::default();
        assert_eq!(p.refine_min_length(), p.l_min);
        assert_eq!(p.depth_limit(0.25), p.max_depth);
        let p = AdaptParams {
            h_min: 0.02,
            ..AdaptParams::default()
        };
        assert_eq!(p.refine_min_length(), 0.04);
        // 0.25 m halved 4 times is 0.0156 m < 0.02 m: 4 levels reach h_min.
        assert_eq!(p.depth_limit(0.25), 4);
        assert_eq!(p.depth_limit(0.01), 0);
    }
}
