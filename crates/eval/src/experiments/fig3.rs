use super::Writer;
pub fn run(_w: &mut Writer, _t: Option<u64>) -> Result<String, String> {
    Err("not yet".into())
}
