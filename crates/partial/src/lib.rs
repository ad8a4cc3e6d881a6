//! A sharded render's partial results: `partial` (the `.fbpart` file a
//! shard writes: its exact sums and where and how it ran) → `merge`
//! (parts checked to be one render covering its work exactly once, then
//! added up bit for bit). Which part of a render a shard does is
//! `fogbank_render::shard`'s; running shards and writing their files is
//! `fogbank`'s.

pub mod merge;
pub mod partial;
