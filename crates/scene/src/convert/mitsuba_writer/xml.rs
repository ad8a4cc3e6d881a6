//! A small XML element tree, written with two-space indentation and its
//! attribute values escaped; numbers are written as the shortest text that
//! reads back as the same `f32`.

use std::fmt::Write;

#[derive(Clone, Debug, PartialEq)]
pub struct El {
    pub tag: &'static str,
    pub attrs: Vec<(&'static str, String)>,
    pub children: Vec<El>,
}

impl El {
    pub fn new(tag: &'static str) -> El {
        El {
            tag,
            attrs: Vec::new(),
            children: Vec::new(),
        }
    }

    /// `<tag type="ty">`.
    pub fn plugin(tag: &'static str, ty: &str) -> El {
        El::new(tag).attr("type", ty)
    }

    pub fn attr(mut self, name: &'static str, value: impl Into<String>) -> El {
        self.attrs.push((name, value.into()));
        self
    }

    pub fn child(mut self, c: El) -> El {
        self.children.push(c);
        self
    }

    pub fn push(&mut self, c: El) {
        self.children.push(c);
    }

    /// `<tag name="name" value="value"/>`.
    fn property(tag: &'static str, name: &str, value: String) -> El {
        El::new(tag).attr("name", name).attr("value", value)
    }

    pub fn float(name: &str, x: f64) -> El {
        El::property("float", name, num(x))
    }

    pub fn integer(name: &str, x: i64) -> El {
        El::property("integer", name, x.to_string())
    }

    pub fn boolean(name: &str, b: bool) -> El {
        El::property("boolean", name, b.to_string())
    }

    pub fn string(name: &str, s: &str) -> El {
        El::property("string", name, s.to_string())
    }

    /// `<rgb>` of three channels.
    pub fn rgb(name: &str, c: [f32; 3]) -> El {
        let v = c.map(|x| num(x as f64));
        El::property("rgb", name, v.join(", "))
    }

    /// `<point name x y z>` (or `<vector>` with `tag`).
    pub fn xyz(tag: &'static str, name: &str, v: [f64; 3]) -> El {
        El::new(tag)
            .attr("name", name)
            .attr("x", num(v[0]))
            .attr("y", num(v[1]))
            .attr("z", num(v[2]))
    }

    /// `<transform name><matrix value="16 numbers, rows"/></transform>`.
    pub fn matrix(name: &str, rows: [[f64; 4]; 4]) -> El {
        let v: Vec<String> = rows.iter().flatten().map(|&x| num(x)).collect();
        El::new("transform")
            .attr("name", name)
            .child(El::new("matrix").attr("value", v.join(" ")))
    }

    /// The element as indented text.
    pub fn write(&self, out: &mut String, depth: usize) {
        let pad = "  ".repeat(depth);
        let _ = write!(out, "{pad}<{}", self.tag);
        for (k, v) in &self.attrs {
            let _ = write!(out, " {k}=\"{}\"", escape(v));
        }
        if self.children.is_empty() {
            out.push_str("/>\n");
            return;
        }
        out.push_str(">\n");
        for c in &self.children {
            c.write(out, depth + 1);
        }
        let _ = writeln!(out, "{pad}</{}>", self.tag);
    }
}

/// `x` as the shortest decimal that reads back as the same `f32` when it
/// is one, else as the shortest that reads back as the same `f64`.
pub fn num(x: f64) -> String {
    let f = x as f32;
    if f as f64 == x {
        format!("{f}")
    } else {
        format!("{x}")
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod xml_test {
    use super::*;

    #[test]
    fn writes_nested_elements_escaped() {
        let e = El::plugin("bsdf", "diffuse").child(El::string("x", "a\"<&"));
        let mut s = String::new();
        e.write(&mut s, 0);
        assert_eq!(
            s,
            "<bsdf type=\"diffuse\">\n  <string name=\"x\" value=\"a&quot;&lt;&amp;\"/>\n</bsdf>\n"
        );
        assert_eq!(num(0.1f32 as f64), "0.1");
        assert_eq!(num(0.1), "0.1");
        assert_eq!(num(1e-7), "0.0000001");
    }
}
