//! `fogbank report`: one offline HTML page gathering the outputs of a set of
//! runs (summaries, tables, images, plots, notes) found below a folder.
//! Images are linked by relative path, so the page works from a copy of the
//! folder without a server.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const MAX_CSV_ROWS: usize = 40;

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            walk(&p, out)?;
        } else {
            out.push(p);
        }
    }
    Ok(())
}

fn csv_table(text: &str) -> String {
    let mut html = String::from("<table>");
    for (i, line) in text.lines().enumerate() {
        if i > MAX_CSV_ROWS {
            let _ = write!(
                html,
                "<tr><td colspan=99>… {} more rows</td></tr>",
                text.lines().count() - i
            );
            break;
        }
        let tag = if i == 0 { "th" } else { "td" };
        html.push_str("<tr>");
        for cell in line.split(',') {
            let _ = write!(html, "<{tag}>{}</{tag}>", escape(cell));
        }
        html.push_str("</tr>");
    }
    html + "</table>"
}

fn json_table(v: &serde_json::Value) -> String {
    let mut html = String::from("<table>");
    if let Some(obj) = v.as_object() {
        for (k, val) in obj {
            let shown = match val {
                serde_json::Value::Number(n) => {
                    n.as_f64().map_or(n.to_string(), |f| format!("{f:.6}"))
                }
                other => other.to_string(),
            };
            let _ = write!(
                html,
                "<tr><th>{}</th><td>{}</td></tr>",
                escape(k),
                escape(&shown)
            );
        }
    }
    html + "</table>"
}

/// Writes `DIR/index.html`; returns its path.
pub fn write_report(dir: &Path) -> Result<PathBuf, String> {
    let mut files = Vec::new();
    walk(dir, &mut files).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut by_folder: std::collections::BTreeMap<PathBuf, Vec<PathBuf>> = Default::default();
    for f in files {
        let rel = f.strip_prefix(dir).unwrap_or(&f).to_path_buf();
        if rel == Path::new("index.html") {
            continue;
        }
        by_folder
            .entry(rel.parent().map(Path::to_path_buf).unwrap_or_default())
            .or_default()
            .push(rel);
    }
    let mut html = String::from(
        "<!doctype html><meta charset=utf-8><title>fogbank report</title><style>\
         body{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222}\
         table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 6px;font-size:90%}\
         img{max-width:100%;margin:4px;border:1px solid #ddd}figure{display:inline-block;margin:4px}\
         figcaption{font-size:80%;color:#555}pre{background:#f6f6f6;padding:.5em;white-space:pre-wrap}</style>",
    );
    let _ = write!(
        html,
        "<h1>fogbank report: {}</h1>",
        escape(&dir.display().to_string())
    );
    for (folder, files) in &by_folder {
        let name = if folder.as_os_str().is_empty() {
            ".".to_string()
        } else {
            folder.display().to_string()
        };
        let _ = write!(html, "<h2>{}</h2>", escape(&name));
        for f in files {
            let ext = f
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            let full = dir.join(f);
            let link = escape(&f.to_string_lossy().replace('\\', "/"));
            match ext.as_str() {
                "png" | "svg" | "jpg" => {
                    let _ = write!(
                        html,
                        "<figure><img src=\"{link}\"><figcaption>{link}</figcaption></figure>"
                    );
                }
                "json" => {
                    if let Ok(v) = std::fs::read_to_string(&full)
                        .map(|t| serde_json::from_str::<serde_json::Value>(&t))
                    {
                        let _ = write!(html, "<h3>{link}</h3>");
                        html.push_str(&v.map(|v| json_table(&v)).unwrap_or_else(|e| {
                            format!("<p>unreadable: {}</p>", escape(&e.to_string()))
                        }));
                    }
                }
                "csv" => {
                    if let Ok(t) = std::fs::read_to_string(&full) {
                        let _ = write!(html, "<h3>{link}</h3>{}", csv_table(&t));
                    }
                }
                "md" | "txt" => {
                    if let Ok(t) = std::fs::read_to_string(&full) {
                        let _ = write!(html, "<h3>{link}</h3><pre>{}</pre>", escape(&t));
                    }
                }
                _ => {
                    let _ = write!(html, "<p><a href=\"{link}\">{link}</a></p>");
                }
            }
        }
    }
    let path = dir.join("index.html");
    std::fs::write(&path, html).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

#[cfg(test)]
mod report_test {
    use super::*;

    #[test]
    fn gathers_tables_images_and_notes() {
        let dir = std::env::temp_dir().join("fogbank_report_test");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("run1")).unwrap();
        std::fs::write(
            dir.join("run1/summary.json"),
            r#"{"mean_std": 0.5, "estimator": "jackknife"}"#,
        )
        .unwrap();
        std::fs::write(dir.join("run1/curve.csv"), "a,b\n1,2\n").unwrap();
        std::fs::write(dir.join("run1/std.png"), b"not really a png").unwrap();
        std::fs::write(dir.join("notes.md"), "finding <b>").unwrap();
        let page = std::fs::read_to_string(write_report(&dir).unwrap()).unwrap();
        assert!(page.contains("<img src=\"run1/std.png\">"));
        assert!(page.contains("<td>0.500000</td>") && page.contains("jackknife"));
        assert!(page.contains("<th>a</th>") && page.contains("<td>2</td>"));
        assert!(page.contains("finding &lt;b&gt;"));
    }
}
