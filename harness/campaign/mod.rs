//! Campaigns: many co-simulations, and the shards that spread them over a
//! cluster.
//!
//! - [`fuzz`]: random scene files, co-simulated one after another.
//! - [`mutation`]: the mutants of a processor's netlist against the judge.
//! - [`sweep`]: speed against accuracy over a grid of configurations;
//!   [`tune`]: the cheapest configuration that meets an error target.
//! - [`shard`]: one long run split into disjoint slices for a cluster's
//!   array job, and the checks that merge them back (docs/scale.md).

pub mod fuzz;
pub mod mutation;
pub mod shard;
pub mod sweep;
pub mod tune;
