//! Fuzz target: parse, check, summarize and render any text; nothing may panic or hang.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The language is UTF-8 text; other bytes are replaced, as a file reader would do.
    let source = String::from_utf8_lossy(data);
    match model::load(&source) {
        Ok(model) => {
            let _ = model.summary().to_string();
            let values = model.require_values();
            let _ = model::render(&values, "fuzz.lag", &source, model::RenderOptions::default());
        }
        Err(errors) => {
            let _ = model::render(&errors.0, "fuzz.lag", &source, model::RenderOptions::default());
            let _ = model::render_short(&errors.0, "fuzz.lag", &source);
        }
    }
});
