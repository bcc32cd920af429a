//! An animation: the figure at each frame of a motion, in one self-contained HTML file (inline
//! SVG, a small inline script: play/pause, a time slider, the coordinates' values, the traces
//! of chosen points). Every frame is drawn by the same pipeline as a still figure, in one view
//! fitted to the whole motion. To stay small, a frame whose markup differs from the first one
//! only in its numbers is stored as those numbers alone (one decimal: a tenth of a pixel); the
//! script puts them back into the first frame's markup.

use std::fmt::Write;

use crate::sample::{Configuration, Sampler};
use crate::scene::{Item, Scene, P3};
use crate::svg::{self, Pt};
use crate::{build, view, DrawError};

/// What to animate besides the motion itself.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AnimationOptions {
    /// Names of points whose paths are drawn.
    pub traces: Vec<String>,
    /// The page title.
    pub title: String,
}

/// The animation of `model` through `frames` (in time order), as HTML text.
///
/// # Errors
/// As [`crate::figure`], for any frame.
pub fn animation(
    model: &model::Model,
    frames: &[Configuration],
    options: &AnimationOptions,
) -> Result<String, DrawError> {
    let Some((first, rest)) = frames.split_first() else {
        return Ok(html(
            model,
            frames,
            &[],
            &options
                .traces
                .iter()
                .map(|name| (name.clone(), Vec::new()))
                .collect::<Vec<_>>(),
            ((0.0, 0.0), (100.0, 100.0)),
            &view::fit(&Scene::default(), None),
            options,
        ));
    };
    let (scene, plane) = build::scene(&Sampler::new(model, first.clone())?, None)?;
    // Symbols keep the first frame's sizes: a block does not breathe as the system moves.
    let size = Some(scene.size);
    let mut scenes = vec![scene];
    for scene in in_parallel(rest, |at| {
        Ok(build::scene(&Sampler::new(model, at.clone())?, size)?.0)
    }) {
        scenes.push(scene?);
    }
    let all = Scene {
        items: scenes
            .iter()
            .flat_map(|s| s.items.iter().cloned())
            .collect(),
        size: scenes.iter().map(|s| s.size).fold(0.0, f64::max),
        unmarked: Vec::new(),
    };
    let view = view::fit(&all, plane);
    let written: Vec<svg::Written> = in_parallel(&scenes, |s| svg::frame(s, &view));
    let mut lo = (f64::INFINITY, f64::INFINITY);
    let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for w in &written {
        lo = (lo.0.min(w.bounds.0 .0), lo.1.min(w.bounds.0 .1));
        hi = (hi.0.max(w.bounds.1 .0), hi.1.max(w.bounds.1 .1));
    }
    if !lo.0.is_finite() {
        (lo, hi) = ((0.0, 0.0), (100.0, 100.0));
    }
    let traces: Vec<(String, Vec<Pt>)> = options
        .traces
        .iter()
        .map(|name| (name.clone(), trace(&scenes, name, &view)))
        .collect();
    Ok(html(
        model,
        frames,
        &written,
        &traces,
        (lo, hi),
        &view,
        options,
    ))
}

/// `f` of each item, in order, computed on as many threads as the machine has cores (at most
/// 8): the frames of an animation are drawn independently of one another.
fn in_parallel<T: Sync, U: Send>(items: &[T], f: impl Fn(&T) -> U + Sync) -> Vec<U> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get().min(8));
    if threads < 2 || items.len() < 2 {
        return items.iter().map(&f).collect();
    }
    let chunk = items.len().div_ceil(threads);
    std::thread::scope(|scope| {
        let handles: Vec<_> = items
            .chunks(chunk)
            .map(|part| scope.spawn(|| part.iter().map(&f).collect::<Vec<U>>()))
            .collect();
        handles
            .into_iter()
            // A panic in a worker is a bug of the drawing; it is passed on as it is.
            .flat_map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    })
}

/// Where point `name` is drawn in each scene (frames where it is not drawn are skipped).
fn trace(scenes: &[Scene], name: &str, view: &view::View) -> Vec<Pt> {
    scenes
        .iter()
        .filter_map(|s| {
            s.items.iter().find_map(|i| match i {
                Item::Particle { name: n, at } | Item::Point { name: n, at } if n == name => {
                    Some(*at)
                }
                Item::Block {
                    name: n, centre, ..
                } if n == name => Some(*centre),
                _ => None,
            })
        })
        .map(|p: P3| view.page(p))
        .collect()
}

/// A frame's markup split into the text between numbers inside tags, and those numbers (as
/// written: digits with at most one point, a minus sign first for a negative one).
fn split(markup: &str) -> (Vec<&str>, Vec<&str>) {
    let bytes = markup.as_bytes();
    let mut pieces = Vec::new();
    let mut numbers = Vec::new();
    let (mut start, mut i, mut in_tag) = (0, 0, false);
    while i < bytes.len() {
        let c = bytes[i];
        if c == b'<' {
            in_tag = true;
        } else if c == b'>' {
            in_tag = false;
        }
        let starts_number = in_tag
            && (c.is_ascii_digit()
                || (c == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit)))
            && i > 0
            && matches!(bytes[i - 1], b'"' | b' ' | b'L' | b'M');
        if starts_number {
            let mut j = i + 1;
            while j < bytes.len() && (bytes[j].is_ascii_digit() || bytes[j] == b'.') {
                j += 1;
            }
            // Of these characters, what `str::parse::<f64>` reads as a number: digits with
            // one point at most.
            if markup[i..j].bytes().filter(|&b| b == b'.').count() <= 1 {
                pieces.push(&markup[start..i]);
                numbers.push(&markup[i..j]);
                start = j;
            }
            i = j;
            continue;
        }
        i += 1;
    }
    pieces.push(&markup[start..]);
    (pieces, numbers)
}

fn js_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '<' => out.push_str("\\u003c"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Appends the number written as `text` (as [`split`] finds it) to a tenth, as [`tenth`]
/// writes the number it reads. Straight from the digits when the hundredths do not make a
/// tie (a written number with at most two decimals lies within 10⁻¹⁵ of its double, and the
/// tenth of that double is then the tenth of the digits); else through the double.
fn tenth_of(out: &mut String, text: &str) {
    let (negative, unsigned) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text),
    };
    let (whole, fraction) = unsigned.split_once('.').unwrap_or((unsigned, ""));
    let digits = fraction.as_bytes();
    let tie = digits.len() == 2 && digits[1] == b'5';
    if whole.len() <= 9 && digits.len() <= 2 && !tie {
        if let Ok(units) = whole.parse::<u64>() {
            let tenths = digits.first().map_or(0, |d| u64::from(d - b'0'));
            let up = u64::from(digits.get(1).is_some_and(|d| *d > b'5'));
            let n = units * 10 + tenths + up;
            write_tenths(out, negative && n > 0, n);
            return;
        }
    }
    match text.parse::<f64>() {
        Ok(x) => tenth(out, x),
        Err(_) => out.push_str(text),
    }
}

/// `n` tenths, without a trailing `.0`.
fn write_tenths(out: &mut String, negative: bool, n: u64) {
    let mut buffer = [0; 24];
    let text = if n % 10 == 0 {
        svg::decimal(&mut buffer, negative, n / 10, 0)
    } else {
        svg::decimal(&mut buffer, negative, n, 1)
    };
    out.push_str(text);
}

/// Appends `x` to a tenth (`{x:.1}`), without a trailing `.0` and with `-0` as `0`.
fn tenth(out: &mut String, x: f64) {
    if let Some((negative, n)) = svg::fixed(x, 10) {
        write_tenths(out, negative && n > 0, n);
        return;
    }
    let start = out.len();
    let _ = write!(out, "{x:.1}");
    if out.ends_with(".0") {
        out.truncate(out.len() - 2);
    }
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

/// The page: the frames, the coordinates' values, the traces, and the script that plays them.
fn html(
    model: &model::Model,
    frames: &[Configuration],
    written: &[svg::Written],
    traces: &[(String, Vec<Pt>)],
    bounds: (Pt, Pt),
    view: &view::View,
    options: &AnimationOptions,
) -> String {
    let (template, data) = frame_data(written);
    let names: Vec<String> = model
        .coordinates()
        .iter()
        .map(|c| js_string(&crate::names::symbol(&c.name.name)))
        .collect();
    let script = Script {
        template,
        data,
        values: values(frames),
        names: format!("[{}]", names.join(",")),
        last: frames.len().saturating_sub(1),
    };
    page(&options.title, bounds, view, &trace_paths(traces), &script)
}

/// The data the page's script reads, each a JavaScript literal.
struct Script {
    /// The first frame's markup cut at its numbers (`T`).
    template: String,
    /// Each frame: its numbers, or its whole markup when it does not fit the template (`F`).
    data: String,
    /// Each frame's time and coordinates (`Q`).
    values: String,
    /// The coordinates' symbols (`N`).
    names: String,
    /// The last frame's index (the slider's end).
    last: usize,
}

/// The template (the first frame's markup cut at its numbers) and every frame as its numbers
/// to a tenth of a pixel, or as its markup when it differs from the template in more than
/// its numbers.
fn frame_data(written: &[svg::Written]) -> (String, String) {
    let (template, _) = written.first().map(|w| split(&w.inner)).unwrap_or_default();
    let mut data = String::from("[");
    for (k, w) in written.iter().enumerate() {
        let (pieces, numbers) = split(&w.inner);
        if k > 0 {
            data.push(',');
        }
        if pieces == template {
            data.push('[');
            for (i, x) in numbers.iter().enumerate() {
                if i > 0 {
                    data.push(',');
                }
                tenth_of(&mut data, x);
            }
            data.push(']');
        } else {
            data.push_str(&js_string(&w.inner));
        }
    }
    data.push(']');
    let pieces: Vec<String> = template.iter().map(|p| js_string(p)).collect();
    (format!("[{}]", pieces.join(",")), data)
}

/// Each frame's time and coordinates, to four decimals.
fn values(frames: &[Configuration]) -> String {
    let rows: Vec<String> = frames
        .iter()
        .map(|f| {
            let row: Vec<String> = std::iter::once(f.time)
                .chain(f.coordinates.iter().copied())
                .map(|x| format!("{x:.4}"))
                .collect();
            format!("[{}]", row.join(","))
        })
        .collect();
    format!("[{}]", rows.join(","))
}

/// The traced points' paths, dashed.
fn trace_paths(traces: &[(String, Vec<Pt>)]) -> String {
    let mut paths = String::new();
    for (name, points) in traces {
        let list: Vec<String> = points
            .iter()
            .map(|p| format!("{} {}", svg::number(p.0), svg::number(p.1)))
            .collect();
        let _ = writeln!(
            paths,
            r##"<polyline id="trace-{name}" points="{}" fill="none" stroke="#9aa7b8" stroke-width="1.2" stroke-dasharray="3 3"/>"##,
            list.join(" ")
        );
    }
    paths
}

/// The HTML page around the picture's box `(lo, hi)`, its traces and its script's data.
fn page(
    title: &str,
    (lo, hi): (Pt, Pt),
    view: &view::View,
    paths: &str,
    script: &Script,
) -> String {
    let (w, h) = (hi.0 - lo.0, hi.1 - lo.1);
    format!(
        r#"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{title}</title>
<style>body{{font-family:'DejaVu Sans',Arial,sans-serif;margin:1em}}#values{{font-family:monospace;margin-top:.5em}}input[type=range]{{width:{slider}px}}</style>
</head><body>
<svg xmlns="http://www.w3.org/2000/svg" viewBox="{x} {y} {w} {h}" width="{w}" height="{h}" data-scale="{scale}" data-origin="{ox} {oy}" data-u="{u0} {u1} {u2}" data-v="{v0} {v1} {v2}">
<style>{style}</style>
<rect x="{x}" y="{y}" width="{w}" height="{h}" fill="white"/>
{paths}<g id="frame"></g>
</svg>
<div><button id="play">pause</button> <input id="time" type="range" min="0" max="{last}" value="0" step="1"></div>
<div id="values"></div>
<script>
const T={template};
const F={data};
const Q={values};
const N={names};
{PLAYER}</script>
</body></html>
"#,
        title = title.replace('<', "&lt;"),
        slider = w.max(200.0).round(),
        x = svg::number(lo.0),
        y = svg::number(lo.1),
        w = svg::number(w),
        h = svg::number(h),
        style = svg::style(),
        scale = view.scale,
        ox = view.origin.0,
        oy = view.origin.1,
        u0 = view.u[0],
        u1 = view.u[1],
        u2 = view.u[2],
        v0 = view.v[0],
        v1 = view.v[1],
        v2 = view.v[2],
        template = script.template,
        data = script.data,
        values = script.values,
        names = script.names,
        last = script.last,
    )
}

/// The script that plays the frames: it rebuilds a frame's markup from the template and its
/// numbers, shows the time and the coordinates, follows the clock while playing, and lets the
/// slider choose a frame (which pauses).
const PLAYER: &str = r#"const g=document.getElementById("frame"),s=document.getElementById("time"),b=document.getElementById("play"),v=document.getElementById("values");
function markup(k){const f=F[k];if(typeof f==="string")return f;let o="";for(let i=0;i<T.length;i++){o+=T[i];if(i<f.length)o+=f[i];}return o;}
function show(k){g.innerHTML=markup(k);s.value=k;const q=Q[k];let t="t = "+q[0].toFixed(3)+" s";for(let i=0;i<N.length;i++)t+="   "+N[i]+" = "+q[i+1].toFixed(4);v.textContent=t;}
let k=0,playing=true,start=null;
function tick(now){if(playing){if(start===null)start=now-1000*(Q[k][0]-Q[0][0]);const t=Q[0][0]+(now-start)/1000;while(k<Q.length-1&&Q[k+1][0]<=t)k++;if(k>=Q.length-1){k=0;start=null;}show(k);}requestAnimationFrame(tick);}
b.onclick=()=>{playing=!playing;start=null;b.textContent=playing?"pause":"play";};
s.oninput=()=>{playing=false;b.textContent="play";k=Number(s.value);show(k);};
show(0);requestAnimationFrame(tick);
"#;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tenths_are_written_as_format_writes_them() {
        let reference = |x: f64| {
            let s = format!("{x:.1}");
            let s = s.strip_suffix(".0").unwrap_or(&s).to_owned();
            if s == "-0" {
                "0".to_owned()
            } else {
                s
            }
        };
        // Every number a frame holds (two decimals, as written), and halves of a tenth.
        for k in -300_000..300_000 {
            let x: f64 = format!("{:.2}", f64::from(k) / 100.0)
                .parse()
                .expect("a number");
            let mut written = String::new();
            tenth(&mut written, x);
            assert_eq!(written, reference(x), "{x}");
            let text = format!("{:.2}", f64::from(k) / 100.0);
            let mut from_text = String::new();
            tenth_of(&mut from_text, &text);
            assert_eq!(from_text, reference(x), "{text}");
        }
        for text in [
            "7",
            "-7",
            "0",
            "-0",
            "12.3",
            "-0.04",
            "-0.05",
            "-0.06",
            "999999.99",
            "1.2.3",
        ] {
            let mut from_text = String::new();
            tenth_of(&mut from_text, text);
            let expected = text.parse().map_or(text.to_owned(), reference);
            assert_eq!(from_text, expected, "{text}");
        }
        for x in [0.05, -0.05, 0.25, -0.25, 1e6, -1e7, 0.0, -0.0, f64::NAN] {
            let mut written = String::new();
            tenth(&mut written, x);
            assert_eq!(written, reference(x), "{x}");
        }
    }

    #[test]
    fn numbers_inside_tags_are_split_out_and_text_is_kept() {
        let (pieces, numbers) =
            split(r#"<line x1="1.25" y1="-3.50"/><text x="2.00">P1 0.50</text>"#);
        assert_eq!(numbers, vec!["1.25", "-3.50", "2.00"]);
        let mut back = String::new();
        for (i, p) in pieces.iter().enumerate() {
            back.push_str(p);
            if let Some(x) = numbers.get(i) {
                back.push_str(x);
            }
        }
        assert_eq!(
            back,
            r#"<line x1="1.25" y1="-3.50"/><text x="2.00">P1 0.50</text>"#
        );
    }
}
