//! The document as JSON, for programs.

use super::{Block, Cell, Document, Math};

impl Document {
    /// The document as JSON: `{title, sections: [{title, level, blocks}]}`, each block tagged
    /// by `kind` with its mathematics in both notations.
    #[must_use]
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::json;
        let math = |m: &Math| json!({ "unicode": m.unicode, "latex": m.latex });
        let sections: Vec<serde_json::Value> = self
            .sections
            .iter()
            .map(|s| {
                let blocks: Vec<serde_json::Value> = s
                    .blocks
                    .iter()
                    .map(|b| match b {
                        Block::Paragraph(p) => json!({ "kind": "paragraph", "text": p }),
                        Block::Remark(p) => json!({ "kind": "remark", "text": p }),
                        Block::List(items) => json!({ "kind": "list", "items": items }),
                        Block::Equations(lines) => json!({
                            "kind": "equations",
                            "lines": lines.iter().map(|e| json!({ "lhs": math(&e.lhs), "rhs": math(&e.rhs) })).collect::<Vec<_>>(),
                        }),
                        Block::Table { header, rows } => json!({
                            "kind": "table",
                            "header": header,
                            "rows": rows.iter().map(|r| r.iter().map(|c| match c {
                                Cell::Text(t) => json!(t),
                                Cell::Math(m) => math(m),
                            }).collect::<Vec<_>>()).collect::<Vec<_>>(),
                        }),
                        Block::Figure { path, caption, .. } => json!({ "kind": "figure", "path": path, "caption": caption }),
                        Block::Link { path, text } => json!({ "kind": "link", "path": path, "text": text }),
                    })
                    .collect();
                json!({ "title": s.title, "level": s.level, "blocks": blocks })
            })
            .collect();
        json!({ "title": self.title, "sections": sections })
    }
}
