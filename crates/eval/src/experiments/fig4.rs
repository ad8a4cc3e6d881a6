use super::Writer;
pub enum Variant {
    Smooth,
    Sparse,
}
pub fn run(_w: &mut Writer, _t: Option<u64>, _v: Variant) -> Result<String, String> {
    Err("not yet".into())
}
