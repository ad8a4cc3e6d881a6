//! `fogbank-partial`'s integration tests, one module per concept, in one
//! binary.

mod shard;
