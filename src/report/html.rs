//! The page around the figures: one self-contained HTML file, styles
//! inline, no scripts, fonts or images from anywhere, printable. Every
//! string that comes from the input passes through [`escape`].

use std::fmt::Write as _;

/// Text made safe for HTML element content and quoted attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "body{font-family:sans-serif;margin:24px auto;max-width:1180px;color:#222;line-height:1.4}\
h1{font-size:1.5em;margin-bottom:0}h2{font-size:1.2em;border-bottom:1px solid #ccc;padding-bottom:2px;margin-top:28px}\
h3{font-size:1.02em;margin-bottom:4px}p.note{color:#555;font-size:.92em;margin-top:2px}\
table{border-collapse:collapse;font-size:.88em;margin:6px 0}td,th{border:1px solid #ccc;padding:2px 7px;text-align:right}\
th{background:#f2f2f2}td.l,th.l{text-align:left}pre{background:#f7f7f7;padding:8px;font-size:.82em;overflow-x:auto;white-space:pre-wrap}\
.figs{display:flex;flex-wrap:wrap;gap:10px}\
p.warn{background:#fff4e0;border-left:4px solid #e08a00;padding:6px 10px}\
p.answer{background:#eef6ee;border-left:4px solid #2c8a2c;padding:6px 10px;font-size:1.02em}.figs>div{break-inside:avoid}svg{max-width:100%;height:auto}\
@media print{body{margin:0;max-width:none}h2{break-after:avoid}}";

/// A page being built: sections of headings, notes, tables and figures.
pub struct Page {
    body: String,
}

impl Page {
    /// A page titled `title` (escaped).
    pub fn new(title: &str) -> Page {
        let mut body = String::new();
        let _ = writeln!(body, "<h1>{}</h1>", escape(title));
        Page { body }
    }

    /// A section heading (text from the tool).
    pub fn section(&mut self, title: &str) {
        let _ = writeln!(self.body, "<h2>{}</h2>", escape(title));
    }

    /// A sub-heading.
    pub fn heading(&mut self, title: &str) {
        let _ = writeln!(self.body, "<h3>{}</h3>", escape(title));
    }

    /// A paragraph of plain text (escaped).
    pub fn note(&mut self, text: &str) {
        let _ = writeln!(self.body, "<p class=\"note\">{}</p>", escape(text));
    }

    /// A warning the reader must not miss (escaped).
    pub(crate) fn warning(&mut self, text: &str) {
        let _ = writeln!(self.body, "<p class=\"warn\">{}</p>", escape(text));
    }

    /// The answer to a question the sweep asks (escaped).
    pub fn answer(&mut self, text: &str) {
        let _ = writeln!(self.body, "<p class=\"answer\">{}</p>", escape(text));
    }

    /// Preformatted text (escaped), e.g. the resolved sweep.
    pub(crate) fn pre(&mut self, text: &str) {
        let _ = writeln!(self.body, "<pre>{}</pre>", escape(text));
    }

    /// A table: header cells and rows, every cell escaped; the first
    /// column is left-aligned.
    pub fn table(&mut self, head: &[&str], rows: &[Vec<String>]) {
        let b = &mut self.body;
        b.push_str("<table><tr>");
        for (i, h) in head.iter().enumerate() {
            let _ = write!(
                b,
                "<th{}>{}</th>",
                if i == 0 { " class=\"l\"" } else { "" },
                escape(h)
            );
        }
        b.push_str("</tr>\n");
        for r in rows {
            b.push_str("<tr>");
            for (i, c) in r.iter().enumerate() {
                let _ = write!(
                    b,
                    "<td{}>{}</td>",
                    if i == 0 { " class=\"l\"" } else { "" },
                    escape(c)
                );
            }
            b.push_str("</tr>\n");
        }
        b.push_str("</table>\n");
    }

    /// A row of figures: SVG drawn by `plots` (its text escaped by
    /// plotters), or, where one could not be drawn, a line saying why.
    pub fn figures(&mut self, figs: Vec<Result<String, String>>) {
        self.body.push_str("<div class=\"figs\">\n");
        for f in figs {
            match f {
                Ok(svg) => {
                    let _ = writeln!(self.body, "<div>{svg}</div>");
                }
                Err(e) => {
                    let _ = writeln!(
                        self.body,
                        "<div><p class=\"note\">figure not drawn: {}</p></div>",
                        escape(&e)
                    );
                }
            }
        }
        self.body.push_str("</div>\n");
    }

    /// The whole document.
    pub fn finish(self, title: &str) -> String {
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
             <title>{}</title><style>{STYLE}</style></head>\n<body>\n{}</body></html>\n",
            escape(title),
            self.body
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_neutralises_markup() {
        assert_eq!(
            escape("<script>alert('x') & \"y\"</script>"),
            "&lt;script&gt;alert(&#39;x&#39;) &amp; &quot;y&quot;&lt;/script&gt;"
        );
    }
}
