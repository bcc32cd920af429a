//! `lagrange solve MODEL`: the whole solution, step by step, as the course writes it — for the
//! terminal, as MyST Markdown, as a standalone LaTeX document, or as JSON.
//!
//! Today the solution answers the first question (kinematics, Lagrangian, Lagrange II, first
//! integrals); reactions, equilibria, linearization and simulation add their sections as they
//! land.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;

use report::document::{Block, Section};

use crate::args::ReportFormat;

/// `lagrange solve MODEL [--format …] [--out DIR]`.
pub fn run(
    path: &Path,
    format: ReportFormat,
    out: Option<&Path>,
    set: &[String],
) -> anyhow::Result<ExitCode> {
    let (model, source) = match super::check::load_with_overrides(path, set)? {
        Ok(loaded) => loaded,
        Err(code) => return Ok(code),
    };
    let (system, equations) = match super::check::derive(path, &model)? {
        Ok(derived) => derived,
        Err(code) => return Ok(code),
    };
    let notation = report::document::Notation::of(&system);
    let mut document =
        report::solution::solution_document(&title(path, &source), &system, &equations);
    if let Some(section) = document.sections.first_mut() {
        if !model.inputs().is_empty() {
            section.paragraph(inputs_sentence(&model, &source));
        }
    }
    // Before the simulation: one-sided contacts stop it where they are lost, as in
    // `lagrange simulate`.
    let computed = match super::reactions::compute(path, &model, &source, &system, Some(&equations))
    {
        Ok(computed) => computed,
        Err(code) => return Ok(code),
    };
    let contacts: Vec<(String, cas::Expr)> = computed
        .iter()
        .flat_map(|c| &c.reactions)
        .filter_map(|r| r.along.map(|(value, _)| (r.name.clone(), value)))
        .collect();
    // Prepared once: the free response starts from its initial state, and the Simulation
    // section runs it.
    let prepared = model.simulation().map(|_| {
        let options = simulation::SimulationOptions {
            stop_events: contacts.iter().map(|(_, value)| *value).collect(),
            ..simulation::SimulationOptions::default()
        };
        simulation::Simulation::prepare(&model, &options)
    });
    match super::equilibria::analysis(&system, &equations) {
        Ok((rest, set, lin)) => {
            let initial = match &prepared {
                Some(Ok(run)) => initial_state(run, &rest.coordinates),
                _ => None,
            };
            document
                .sections
                .extend(report::solution_equilibria::equilibria_sections(
                    &rest,
                    &set,
                    &lin,
                    &notation,
                    initial.as_ref(),
                ))
        }
        Err(why) => {
            let mut section = Section::new("Equilibria and their stability", 2);
            section.paragraph(format!("Not analysed: {why}."));
            document.sections.push(section);
        }
    }
    if let Some(dir) = out {
        // Before the sections: the simulation writes its plots there.
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the directory `{}`", dir.display()))?;
    }
    if let Some(prepared) = prepared {
        document
            .sections
            .push(simulation_section(path, prepared, &contacts, out, format));
    }
    let mut disagree = false;
    if let Some(computed) = computed {
        disagree = computed
            .reactions
            .iter()
            .any(|r| r.agreement == mechanics::Agreement::Disagree);
        document
            .sections
            .push(report::solution_reactions::reactions_section(
                &computed.reactions,
                &computed.unilateral,
                &notation,
            ));
    }
    let text = match format {
        ReportFormat::Text => document.to_text(),
        ReportFormat::Md => document.to_markdown(),
        ReportFormat::Tex => document.to_latex(),
        ReportFormat::Json => {
            let mut value = report::eom_json(&system, &equations);
            if let Some(object) = value.as_object_mut() {
                object.insert("report".into(), document.to_json());
            }
            serde_json::to_string_pretty(&value)? + "\n"
        }
    };
    match out {
        None => print!("{text}"),
        Some(dir) => {
            let stem = path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("solution");
            let file = dir.join(format!("{stem}.{}", format.extension()));
            std::fs::write(&file, text)
                .with_context(|| format!("cannot write `{}`", file.display()))?;
            println!("wrote {}", file.display());
        }
    }
    // Two methods that disagree on a reaction are a bug in lagrange, and the exit code says so.
    Ok(if disagree {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    })
}

/// The simulation's initial state by `coordinates` (the rest equations' order); `None` when a
/// coordinate is not among the simulated ones.
fn initial_state(
    run: &simulation::Simulation,
    coordinates: &[String],
) -> Option<report::solution_equilibria::InitialState> {
    let columns = run.columns();
    let state = run.initial_state();
    let n = state.len() / 2;
    let index = |q: &String| columns.iter().skip(1).take(n).position(|c| c == q);
    let mut positions = Vec::with_capacity(coordinates.len());
    let mut rates = Vec::with_capacity(coordinates.len());
    for q in coordinates {
        let k = index(q)?;
        positions.push(*state.get(k)?);
        rates.push(*state.get(n + k)?);
    }
    Some(report::solution_equilibria::InitialState { positions, rates })
}

/// The report's title: the first sentence of the model file's opening comment, else the
/// file name.
fn title(path: &Path, source: &str) -> String {
    let opening: Vec<&str> = source
        .lines()
        .map(str::trim)
        .skip_while(|l| l.is_empty())
        .take_while(|l| l.starts_with('#') && l.trim_start_matches('#').trim() != "")
        .map(|l| l.trim_start_matches('#').trim())
        .collect();
    let paragraph = opening.join(" ");
    let sentence = match paragraph.find(". ") {
        Some(end) => &paragraph[..end],
        None => paragraph.trim_end_matches('.'),
    };
    if sentence.is_empty() {
        path.display().to_string()
    } else {
        sentence.trim_end_matches(':').to_string()
    }
}

/// The inputs as the user wrote them: `Inputs: F = 0, C = 0.`
fn inputs_sentence(model: &model::Model, source: &str) -> String {
    let items: Vec<String> = model
        .inputs()
        .iter()
        .map(|input| match &input.value {
            Some(value) => {
                let written = source.get(value.span.start..value.span.end).unwrap_or("…");
                format!("{} = {}", input.name.name, written.trim())
            }
            None => format!("{} (symbolic)", input.name.name),
        })
        .collect();
    format!(
        "Inputs (given functions of time, held at these values unless set): {}.",
        items.join(", ")
    )
}

/// The "Simulation" section: the model's own `simulate` settings, run once; with `--out`, the
/// plots (time histories, phase portraits, energy error) are written beside the report: SVG
/// for Markdown and the terminal, PNG for LaTeX (which `pdflatex` cannot include as SVG).
fn simulation_section(
    path: &Path,
    prepared: Result<simulation::Simulation, simulation::SimulationError>,
    contacts: &[(String, cas::Expr)],
    out: Option<&Path>,
    format: ReportFormat,
) -> Section {
    let mut section = Section::new("Simulation", 2);
    let mut run = match prepared {
        Ok(run) => run,
        Err(error) => {
            section.paragraph(format!("Not simulated: {error}."));
            return section;
        }
    };
    let columns = run.columns();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let outcome = run.run(&mut |row| rows.push(row.to_vec()));
    let (t_start, t_end) = run.span();
    let stats = outcome.stats;
    section.paragraph(format!(
        "The nonlinear equations of motion integrated from t = {t_start} to t = {t_end} by {} \
         from the model's initial state: {} steps ({} rejected), {} evaluations of the \
         right-hand side.",
        run.method(),
        stats.steps,
        stats.rejected,
        stats.evaluations
    ));
    if let Some(last) = rows.last() {
        let n = (columns.len().saturating_sub(3)) / 2;
        let state: Vec<String> = columns
            .iter()
            .zip(last)
            .skip(1)
            .take(2 * n)
            .map(|(c, v)| format!("{c} = {v:.6}"))
            .collect();
        section.paragraph(format!(
            "At t = {:.6}: {}. Relative energy error {:.2e}, constraint drift {:.2e}.",
            last[0],
            state.join(", "),
            last.get(columns.len() - 2).copied().unwrap_or(f64::NAN),
            last.get(columns.len() - 1).copied().unwrap_or(f64::NAN)
        ));
    }
    match outcome.stop {
        numeric::StopReason::Finished => {}
        numeric::StopReason::Event { index, t } => {
            let why = match contacts.get(index) {
                Some((name, _)) => format!(
                    "the one-sided constraint `{name}` is lost there (its reaction changes sign), \
                     and past that point the equations describe a motion that cannot happen"
                ),
                None => "its stop condition was met".to_string(),
            };
            section.remark(format!("The run stopped at t = {t:.6}: {why}."));
        }
        numeric::StopReason::Failed(failure) => {
            section.remark(format!(
                "The run stopped {failure}; what is shown was computed up to then."
            ));
        }
        _ => {}
    }
    match out {
        Some(dir) => {
            let stem = path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("solution");
            let extension = match format {
                ReportFormat::Tex => "png",
                _ => "svg",
            };
            let file = format!("{stem}-motion.{extension}");
            match report::plot_run(&dir.join(&file), stem, &columns, &rows) {
                Ok(()) => section.blocks.push(Block::Figure {
                    path: file,
                    caption: "Time histories, phase portraits and energy error of the run.".into(),
                }),
                Err(error) => {
                    section.paragraph(format!("The plot could not be written: {error}."));
                }
            }
        }
        None => {
            section.paragraph("With --out DIR the plots are written beside the report.");
        }
    }
    section
}
