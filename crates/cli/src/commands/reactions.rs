//! `lagrange reactions MODEL`: the constraint reactions a model asks for, by Lagrange I and
//! Newton–Euler, for people or as JSON.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use cas::print::to_unicode;
use mechanics::{Agreement, Reaction, Unilateral};
use report::UnilateralReport;

use crate::args::EomFormat;

/// The reactions a model asks for, with the coordinates they are written in and the
/// one-sided analysis of each contact or rope.
pub struct Computed {
    /// The independent coordinates of the constrained system.
    pub coordinates: Vec<String>,
    /// The reactions, in the model's order.
    pub reactions: Vec<Reaction>,
    /// For each reaction, its unilateral analysis when it pushes or pulls only.
    pub unilateral: Vec<Option<UnilateralReport>>,
}

/// Computes the reactions the model asks for; `Ok(None)` when it asks for none. Errors are
/// printed (with the line and column where they come from the file) and become the exit code.
pub fn compute(
    path: &Path,
    model: &model::Model,
    source: &str,
    system: &mechanics::System,
    derived: Option<&mechanics::Equations>,
) -> Result<Option<Computed>, ExitCode> {
    let requests = match model::reaction_requests(model) {
        Ok(requests) => requests,
        Err(error) => {
            let at = model::line_col(source, error.span().start);
            eprintln!(
                "error: {}:{}:{}: {error}",
                path.display(),
                at.line,
                at.column
            );
            return Err(ExitCode::from(1));
        }
    };
    if requests.is_empty() {
        return Ok(None);
    }
    // The equations of the constrained system, derived here unless the caller has them.
    let owned;
    let equations = match derived {
        Some(equations) => Some(equations),
        None => {
            owned = mechanics::derive(system).ok();
            owned.as_ref()
        }
    };
    let found = match equations {
        Some(equations) => mechanics::reactions_of(system, equations, &requests),
        None => mechanics::reactions(system, &requests),
    };
    let reactions = match found {
        Ok(r) => r,
        Err(error) => {
            eprintln!("error: {error}");
            return Err(ExitCode::from(1));
        }
    };
    let coordinates = equations
        .as_ref()
        .map(|eq| eq.coordinates().to_vec())
        .unwrap_or_default();
    let unilateral: Vec<Option<UnilateralReport>> = reactions
        .iter()
        .map(|r| {
            // A contact, a rope, or a rolling contact with its normal: all push or pull only.
            let (value, _) = r.along?;
            let equations = equations.as_ref()?;
            Some(UnilateralReport {
                along_motion: mechanics::along_motion(equations, value),
                scan: scan(model, system, equations, value),
            })
        })
        .collect();
    Ok(Some(Computed {
        coordinates,
        reactions,
        unilateral,
    }))
}

/// Computes and prints the reactions of a model file.
pub fn run(path: &Path, format: EomFormat, set: &[String]) -> anyhow::Result<ExitCode> {
    let (model, source) = match super::check::load_with_overrides(path, set)? {
        Ok(loaded) => loaded,
        Err(code) => return Ok(code),
    };
    let system = model::lower(&model).context("cannot lower the model")?;
    let Computed {
        coordinates,
        reactions,
        unilateral,
    } = match compute(path, &model, &source, &system, None) {
        Ok(Some(computed)) => computed,
        Ok(None) => {
            eprintln!(
                "error: the model asks for no reaction; add `reactions CONSTRAINT` or `reaction NAME: hinge P on BODY`"
            );
            return Ok(ExitCode::from(1));
        }
        Err(code) => return Ok(code),
    };
    match format {
        EomFormat::Json => {
            let value = report::reactions_json(&coordinates, &reactions, &unilateral);
            println!("{}", serde_json::to_string_pretty(&value)?);
        }
        EomFormat::Text => {
            for (i, r) in reactions.iter().enumerate() {
                if i > 0 {
                    println!();
                }
                print_reaction(r, unilateral.get(i).and_then(Option::as_ref));
            }
        }
    }
    let disagree = reactions.iter().any(|r| r.agreement == Agreement::Disagree);
    Ok(if disagree {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    })
}

/// The sign scan from the model's initial state, with the parameters' values.
fn scan(
    model: &model::Model,
    system: &mechanics::System,
    equations: &mechanics::Equations,
    value: cas::Expr,
) -> Option<Unilateral> {
    let [q] = equations.coordinates() else {
        return None;
    };
    let mut initial = (0.0, 0.0);
    for i in model.initial() {
        if &model.coordinate(i.coordinate).name.name == q {
            let x = model.evaluate_constant(&i.value)?;
            if i.rate {
                initial.1 = x;
            } else {
                initial.0 = x;
            }
        }
    }
    let parameters: Vec<(String, f64)> = system
        .parameters()
        .iter()
        .filter_map(|(name, v)| Some((name.clone(), v.as_ref()?.eval(&|_| None).ok()?)))
        .collect();
    let lookup = |s: cas::Symbol| {
        parameters
            .iter()
            .find(|(name, _)| name == s.name())
            .map(|(_, v)| *v)
    };
    mechanics::scan_unilateral(equations, value, initial, &lookup)
}

fn print_reaction(r: &Reaction, unilateral: Option<&UnilateralReport>) {
    let kind = r.kind.map_or("constraint", |k| k.word());
    match &r.point {
        Some((point, _)) => println!(
            "{} — {kind} at {point}, on {}:",
            r.name,
            r.members.join(", ")
        ),
        None if r.driving => println!(
            "{} — driven coordinate, the generalized force that drives it:",
            r.name
        ),
        None => println!("{} — {kind}, generalized reaction:", r.name),
    }
    if let Some(f) = &r.force {
        for (axis, x) in ["x", "y", "z"].iter().zip(f) {
            if !x.is_zero() {
                println!("  R_{axis} = {}", to_unicode(*x));
            }
        }
        if f.iter().all(|x| x.is_zero()) {
            println!("  R = 0");
        }
    }
    if let Some(c) = &r.couple {
        for (axis, x) in ["x", "y", "z"].iter().zip(c) {
            if !x.is_zero() {
                println!("  C_{axis} = {}", to_unicode(*x));
            }
        }
        if c.iter().all(|x| x.is_zero()) {
            println!("  C = 0");
        }
    }
    if let Some(c) = &r.unbalanced_couple {
        let parts: Vec<String> = ["x", "y", "z"]
            .iter()
            .zip(c)
            .filter(|(_, x)| !x.is_zero())
            .map(|(axis, x)| format!("C_{axis} = {}", to_unicode(*x)))
            .collect();
        println!(
            "  note: the motion also needs a couple about this point ({}), which a {} does not transmit: loads the release cannot attribute to these bodies act on them (other supports built into the coordinates, whose forces R then includes, or generalized forces), or the joint transmits a couple (ask for a clamp)",
            parts.join(", "),
            r.kind.map_or("constraint", |k| k.word())
        );
    }
    if let Some(f) = &r.friction {
        for (axis, x) in ["x", "y", "z"].iter().zip(f) {
            if !x.is_zero() {
                println!("  friction F_{axis} = {}", to_unicode(*x));
            }
        }
    }
    if let Some((value, _)) = &r.along {
        let (symbol, sign) = match r.kind {
            Some(mechanics::ReleaseKind::Rope) => {
                ("T", "pull only: the rope goes slack where T < 0")
            }
            _ => ("N", "push only: contact is lost where N < 0"),
        };
        println!("  {symbol} = {}   ({sign})", to_unicode(*value));
        if let Some(u) = unilateral {
            if let Some(along) = u.along_motion {
                println!(
                    "  along the motion (energy integral h = h₀): {symbol} = {}",
                    to_unicode(along)
                );
            }
            match &u.scan {
                Some(Unilateral::Lost {
                    coordinate,
                    value,
                    rate,
                }) => println!(
                    "  from the initial state, {symbol} changes sign at {coordinate} = {value:.6} (cos = {:.6}, rate {rate:.6}): the constraint is lost there",
                    value.cos()
                ),
                Some(Unilateral::LostAtStart) => {
                    println!("  {symbol} < 0 at the initial state: the constraint does not hold")
                }
                Some(Unilateral::Kept {
                    coordinate,
                    turning_point: Some(q),
                }) => println!(
                    "  from the initial state, {symbol} keeps its sign up to the turning point {coordinate} = {q:.6}"
                ),
                _ => {}
            }
        }
    }
    for (q, e) in &r.generalized {
        let label = if r.driving { "Q_drive" } else { "Q^R" };
        println!("  {label}_{q} = {}", to_unicode(*e));
    }
    for (k, l) in r.multipliers.iter().enumerate() {
        println!("  λ{} = {}", k + 1, to_unicode(*l));
    }
    let methods: Vec<&str> = r.methods.iter().map(|m| m.name()).collect();
    println!(
        "  methods: {} — {}",
        methods.join(", "),
        r.agreement.verdict()
    );
}
