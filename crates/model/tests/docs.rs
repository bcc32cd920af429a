//! The examples of `docs/language.md` are valid syntax: every `text` code block that is a
//! model snippet parses without a diagnostic (snippets use names they do not declare, so they
//! are only parsed; the complete model at the top is also checked).

fn blocks(markdown: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in markdown.lines() {
        match (&mut current, line.trim_start()) {
            (None, "```text") => current = Some(String::new()),
            (Some(block), "```") => {
                blocks.push(std::mem::take(block));
                current = None;
            }
            (Some(block), _) => {
                block.push_str(line.trim_start_matches("  "));
                block.push('\n');
            }
            _ => {}
        }
    }
    blocks
}

#[test]
fn reference_snippets_parse() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/language.md");
    let markdown = std::fs::read_to_string(path).expect("docs/language.md");
    let blocks = blocks(&markdown);
    assert!(blocks.len() > 25, "found only {} blocks", blocks.len());
    let mut snippets = 0;
    for block in &blocks {
        // Skip program output, rendered diagnostics and the grammar.
        let first = block.trim_start();
        if first.starts_with("degrees of freedom")
            || first.starts_with('[')
            || first.starts_with("file ")
        {
            continue;
        }
        snippets += 1;
        let (_, diagnostics) = model::parse(block);
        assert!(
            diagnostics.is_empty(),
            "snippet does not parse:\n{block}\n{diagnostics:#?}"
        );
    }
    assert!(snippets > 20);
    // The first block is a complete model.
    let first = blocks.first().expect("a first block");
    if let Err(errors) = model::load(first) {
        panic!(
            "{}",
            model::render(&errors.0, "docs", first, model::RenderOptions::default())
        );
    }
}
