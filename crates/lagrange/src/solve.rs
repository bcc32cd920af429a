//! The whole solution of a system, step by step as the course writes it (what `lagrange
//! solve` prints): kinematics, the Lagrangian, Lagrange's equations, first integrals,
//! equilibria and their stability, the linearized dynamics, the model's own simulation and
//! the reactions asked for — each part from the [`Analysis`], computed once.

use std::path::{Path, PathBuf};

use mechanics::equilibria::EquilibriumError;
use report::document::{Block, Document, Notation, Section};
use report::solution_simulation::{simulation_section, RunEnd, RunReport};

use crate::simulate::{run_sampled, Ending, SimulationOptions};
use crate::{Analysis, Error, Reactions};

/// About how many rows of its simulation a solution keeps for the plot (at most twice as
/// many, evenly spread, and the last).
pub const PLOTTED_ROWS: usize = 5_000;

/// The intervals between the plotted rows of a solution's simulation when the model gives no
/// output step.
const PLOT_INTERVALS: f64 = 1_000.0;

/// Image pixels per SVG pixel of the figure of a LaTeX solution (PNG).
pub const PNG_SCALE: f64 = 2.0;

/// Frames per second of simulated time of a solution's animation.
pub const ANIMATION_FPS: f64 = 30.0;

/// Where the solution's figures go.
#[derive(Debug, Clone)]
pub struct Figures {
    /// The directory (beside the report).
    pub directory: PathBuf,
    /// The file name's stem (`7.1-cart-pendulum` → `7.1-cart-pendulum.svg` for the system,
    /// `7.1-cart-pendulum.html` for its animation, `7.1-cart-pendulum-motion.svg` for the plots).
    pub stem: String,
    /// `svg`, or `png` for LaTeX (which `pdflatex` cannot include as SVG).
    pub extension: &'static str,
}

/// A solution: the document and what it found.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The document, to render as text, Markdown, LaTeX or JSON.
    pub document: Document,
    /// Whether Lagrange I and Newton–Euler disagree on a reaction (a bug of lagrange).
    pub disagree: bool,
}

impl Analysis {
    /// The solution; `figures` says where the figure of the system, its animation and the
    /// plots go (none without it).
    ///
    /// # Errors
    /// As [`Analysis::equations`]: without equations of motion there is no solution. The
    /// later parts (equilibria, simulation, reactions) say in the document why they are
    /// missing.
    pub fn solution(&self, figures: Option<&Figures>) -> Result<Solution, Error> {
        // Checked first, in milliseconds: the Lagrange route of such a model would take
        // seconds to reach its work limit.
        if self.simulation_method() == crate::Method::Kane {
            return self.kane_solution(figures);
        }
        let equations = self.equations()?;
        let system = self.system();
        let notation = Notation::of(system);
        let mut document =
            report::solution::solution_document_in(&self.title(), system, equations, &notation);
        if let (Some(section), Some(sentence)) =
            (document.sections.first_mut(), self.inputs_sentence())
        {
            section.paragraph(sentence);
        }
        if let (Some(figures), Some(section)) = (figures, document.sections.first_mut()) {
            self.figure_part(figures, section);
        }
        let initial = self.initial_state().ok();
        match self.equilibria() {
            Ok(e) => {
                let state = initial
                    .as_ref()
                    .and_then(|s| initial_by_name(equations.coordinates(), s, &e.rest.coordinates));
                document
                    .sections
                    .extend(report::solution_equilibria::equilibria_sections(
                        &e.rest,
                        &e.set,
                        &e.linearized,
                        &notation,
                        state.as_ref(),
                    ));
                pole_paragraphs(e, &notation, &mut document.sections);
                self.condition_paragraphs(&mut document.sections, e);
            }
            Err(why) => {
                let mut section = Section::new("Equilibria and their stability", 2);
                section.paragraph(format!("Not analysed: {why}."));
                document.sections.push(section);
                if matches!(why, Error::Equilibria(EquilibriumError::TimeDependent)) {
                    document.sections.push(self.floquet_part());
                }
            }
        }
        if self.describes_steady_motion() {
            document.sections.push(self.steady_section());
        }
        // Before the simulation, whose one-sided contacts then reuse them.
        let reactions = self.reactions();
        let has_statement = self
            .source()
            .is_some_and(|s| s.model.simulation().is_some());
        if has_statement {
            document.sections.push(self.simulation_part(figures));
        }
        let mut disagree = false;
        match reactions {
            Ok(Some(Reactions {
                numeric: Some(start),
                ..
            })) => document
                .sections
                .push(self.numeric_reactions_section(start)),
            Ok(Some(reactions)) => {
                disagree = reactions.disagree();
                let mut section = report::solution_reactions::reactions_section(
                    &reactions.reactions,
                    &reactions.unilateral,
                    &self.reaction_working(),
                    &notation,
                );
                self.projection_part(&mut section, &notation);
                document.sections.push(section);
            }
            Ok(None) => {}
            // The rest of the solution stands; the section says why the reactions are missing.
            Err(why) => {
                let mut section = Section::new("Constraint reactions", 2);
                section.paragraph(format!("Not derived: {why}."));
                document.sections.push(section);
            }
        }
        document.sections.splice(0..0, self.prose_sections());
        Ok(Solution { document, disagree })
    }

    /// The reactions projected where the model asks (`… in frame R`, `… along n`), at the
    /// end of the reactions section; what cannot be projected is said there.
    fn projection_part(&self, section: &mut Section, notation: &Notation) {
        match self.projected_reactions() {
            Ok(projected) => {
                for p in &projected {
                    report::solution_reactions::projection_blocks(
                        section,
                        &report::solution_reactions::Projection {
                            name: &p.name,
                            onto: &p.onto,
                            components: &p.components,
                            at_equilibria: &p.at_equilibria,
                        },
                        notation,
                    );
                }
            }
            Err(why) => {
                section.paragraph(format!("Not projected: {why}."));
            }
        }
    }

    /// The model's problem statement ("Problem", one paragraph per `problem` statement) and
    /// its notes ("Notes on the model", a list), before the solution proper.
    pub(crate) fn prose_sections(&self) -> Vec<Section> {
        let Some(source) = self.source() else {
            return Vec::new();
        };
        let prose = source.model.prose();
        let mut sections = Vec::new();
        if !prose.problem.is_empty() {
            let mut section = Section::new("Problem", 2);
            for paragraph in &prose.problem {
                section.paragraph(paragraph.clone());
            }
            sections.push(section);
        }
        if !prose.notes.is_empty() {
            let mut section = Section::new("Notes on the model", 2);
            section.blocks.push(Block::List(prose.notes.clone()));
            sections.push(section);
        }
        sections
    }

    /// The solution as JSON: the equations of motion (docs/json.md) with the document under
    /// `report`.
    ///
    /// # Errors
    /// As [`Analysis::solution`].
    pub fn solution_json(&self, solution: &Solution) -> Result<serde_json::Value, Error> {
        if self.simulation_method() == crate::Method::Kane {
            return self.kane_solution_json(solution);
        }
        let mut value = report::eom_json(self.system(), self.equations()?);
        if let Some(object) = value.as_object_mut() {
            object.insert("report".into(), solution.document.to_json());
        }
        Ok(value)
    }

    /// The exercise's figure at the top of the first section, written beside the document
    /// (`STEM.svg`, or `STEM.png` for LaTeX), and for an SVG document with a `simulate`
    /// statement the animation of the motion (`STEM.html`), linked. What cannot be drawn
    /// or written is said in the section instead.
    pub(crate) fn figure_part(&self, figures: &Figures, section: &mut Section) {
        let mut blocks = Vec::new();
        let file = format!("{}.{}", figures.stem, figures.extension);
        let written = self
            .figure(0.0)
            .map_err(|e| e.to_string())
            .and_then(|figure| {
                let bytes = if figures.extension == "png" {
                    figure.png(PNG_SCALE).map_err(|e| e.to_string())?
                } else {
                    figure.svg.into_bytes()
                };
                std::fs::write(figures.directory.join(&file), bytes)
                    .map_err(|e| format!("cannot write `{file}`: {e}"))
            });
        blocks.push(match written {
            Ok(()) => Block::Figure {
                path: file,
                caption: "The system at its initial state.".into(),
                width: 50,
            },
            Err(why) => Block::Paragraph(format!("The figure could not be drawn: {why}.")),
        });
        let simulated = self
            .source()
            .is_some_and(|s| s.model.simulation().is_some());
        if figures.extension == "svg" && simulated {
            let file = format!("{}.html", figures.stem);
            let written = self
                .animation(None, ANIMATION_FPS, &[])
                .map_err(|e| e.to_string())
                .and_then(|page| {
                    std::fs::write(figures.directory.join(&file), page)
                        .map_err(|e| format!("cannot write `{file}`: {e}"))
                });
            blocks.push(match written {
                Ok(()) => Block::Link {
                    path: file,
                    text: "The motion, animated (opens in a browser)".into(),
                },
                Err(why) => Block::Paragraph(format!("The motion could not be animated: {why}.")),
            });
        }
        section.blocks.splice(0..0, blocks);
    }

    /// The "Floquet analysis" section of a model whose equations depend on time: about its
    /// periodic motions when they are periodic, else why not.
    fn floquet_part(&self) -> Section {
        let found = self.floquet(&crate::FloquetOptions::default());
        report::floquet::floquet_section(
            found
                .as_ref()
                .map(|f| &f.results[..])
                .map_err(ToString::to_string),
        )
    }

    /// The "Simulation" section: the model's own settings, run once.
    pub(crate) fn simulation_part(&self, figures: Option<&Figures>) -> Section {
        let mut options = SimulationOptions::default();
        if let Ok(settings) = self.settings(&options) {
            // Rows at the accepted steps are far apart with an 8th-order method, and the plot
            // would be a polygon; without a step of the model's, evenly spaced rows from the
            // dense output draw the curve.
            if settings.output_step.is_none() {
                let span = settings.t_end - settings.t_start;
                options.output_step = Some(span / PLOT_INTERVALS);
            }
        }
        let mut simulation = match self.simulation(&options) {
            Ok(s) => s,
            Err(Error::Located {
                message,
                line,
                column,
                ..
            }) => {
                return simulation_section(Err(format!("line {line}, column {column}: {message}")))
            }
            Err(error) => return simulation_section(Err(error.to_string())),
        };
        // The section shows the last state and a plot: a bounded sample of the rows is
        // enough, however long the run (its steps and rows are bounded by the limits).
        let run = run_sampled(&mut simulation, PLOTTED_ROWS);
        let end = match &run.ending {
            Ending::Finished => RunEnd::Finished,
            Ending::ContactLost { constraint } => RunEnd::ContactLost {
                constraint: constraint.clone(),
                t: run.t,
            },
            Ending::Condition { .. } => RunEnd::Condition { t: run.t },
            Ending::Failed(failure) => RunEnd::Failed(failure.to_string()),
            // A sampled run has no output limit and no caller to halt it.
            other => RunEnd::Failed(format!("at t = {}: {}", run.t, other.word())),
        };
        // The energy balance and the outputs are read off Lagrange's equations, which a run
        // on Kane's route goes without (their derivation is what it avoids).
        let (extras, balance) = if simulation.by_kane() {
            (report::PlotExtras::default(), None)
        } else {
            self.plot_extras(&run)
        };
        let figure = figures.map(|f| {
            let file = format!("{}-motion.{}", f.stem, f.extension);
            let (reactions, rows) = self.rows_with_reactions(&simulation, &run.rows);
            let extras = report::PlotExtras {
                reactions,
                ..extras.clone()
            };
            let path = f.directory.join(&file);
            let rows = rows.as_deref().unwrap_or(&run.rows);
            report::plot_run_with(&path, &f.stem, &run.columns, rows, &extras)
                .map(|()| file)
                .map_err(|e| e.to_string())
        });
        let report = RunReport {
            method: run.method.to_string(),
            span: run.span,
            work: (run.stats.steps, run.stats.rejected, run.stats.evaluations),
            columns: &run.columns,
            last: run.rows.last().map(Vec::as_slice),
            end,
            corrected: simulation
                .initial_correction()
                .map(|c| c.describe(&run.columns)),
            figure,
            balance,
            outputs: extras.outputs.iter().map(|o| o.label.clone()).collect(),
        };
        simulation_section(Ok(&report))
    }

    /// The reactions panel's columns and the rows with the reactions appended (evaluated
    /// numerically at each row's state); no columns and no rows when the model asks for no
    /// reaction or they cannot be evaluated (the plot then has no panel).
    fn rows_with_reactions(
        &self,
        simulation: &simulation::Simulation,
        rows: &[Vec<f64>],
    ) -> (Vec<String>, Option<Vec<Vec<f64>>>) {
        if simulation.by_kane() {
            return (Vec::new(), None);
        }
        let Ok(Some(probe)) = self.reaction_probe() else {
            return (Vec::new(), None);
        };
        let mut copy = simulation.clone();
        let n = (simulation.columns().len() - 3) / 2;
        let extended = rows
            .iter()
            .map(|row| {
                let mut row = row.clone();
                let values = probe.at(&mut copy, row[0], &row[1..=2 * n]);
                row.extend(values);
                row
            })
            .collect();
        (probe.columns(), Some(extended))
    }

    /// The report's title: the model's `title`, else the first sentence of its opening
    /// comment, else the file name, else "Solution".
    #[must_use]
    pub fn title(&self) -> String {
        let Some(source) = self.source() else {
            return "Solution".into();
        };
        if let Some((title, _)) = &source.model.prose().title {
            return title.clone();
        }
        let opening: Vec<&str> = source
            .text
            .lines()
            .map(str::trim)
            .skip_while(|l| l.is_empty())
            .take_while(|l| l.starts_with('#') && l.trim_start_matches('#').trim() != "")
            .map(|l| l.trim_start_matches('#').trim())
            .collect();
        let paragraph = opening.join(" ");
        let sentence = match first_sentence_end(&paragraph) {
            Some(end) => &paragraph[..end],
            None => paragraph.trim_end_matches('.'),
        };
        if sentence.is_empty() {
            source
                .path
                .as_deref()
                .map_or_else(|| "Solution".into(), |p: &Path| p.display().to_string())
        } else {
            sentence.trim_end_matches(':').to_string()
        }
    }

    /// The inputs as the user wrote them: `Inputs (…): F = 0, C = 0.`
    fn inputs_sentence(&self) -> Option<String> {
        let source = self.source()?;
        let inputs = source.model.inputs();
        if inputs.is_empty() {
            return None;
        }
        let items: Vec<String> = inputs
            .iter()
            .map(|input| match &input.value {
                Some(value) => {
                    let written = source
                        .text
                        .get(value.span.start..value.span.end)
                        .unwrap_or("…");
                    format!("{} = {}", input.name.name, written.trim())
                }
                None => format!("{} (symbolic)", input.name.name),
            })
            .collect();
        Some(format!(
            "Inputs (given functions of time, held at these values unless set): {}.",
            items.join(", ")
        ))
    }
}

/// The initial state ordered by `wanted` (the rest equations' coordinates); `None` when one
/// of them is not among the equations' coordinates.
fn initial_by_name(
    coordinates: &[String],
    state: &[f64],
    wanted: &[String],
) -> Option<report::solution_equilibria::InitialState> {
    let n = coordinates.len();
    let mut positions = Vec::with_capacity(wanted.len());
    let mut rates = Vec::with_capacity(wanted.len());
    for q in wanted {
        let k = coordinates.iter().position(|c| c == q)?;
        positions.push(*state.get(k)?);
        rates.push(*state.get(n + k)?);
    }
    Some(report::solution_equilibria::InitialState { positions, rates })
}

/// Beneath the equilibria and the linearized dynamics, what the regular chart at a pole of the
/// coordinates decided and gave (`crate::chart`, `crate::chart_modes`): the model's
/// coordinates cannot decide there, and the table says so.
fn pole_paragraphs(found: &crate::Equilibria, notation: &Notation, sections: &mut [Section]) {
    let name = |q: &str| notation.math(cas::Expr::coordinate(q)).unicode;
    for section in sections.iter_mut() {
        let stability = section.title == "Equilibria and their stability";
        let linearized = section.title == "Linearized dynamics";
        for (i, (pole, modes)) in found.at_poles.iter().zip(&found.pole_modes).enumerate() {
            if let (true, Some(crate::AtPole::Rest(p))) = (stability, pole) {
                let (polar, azimuth) = (name(&p.polar), name(&p.azimuth));
                let eigenvalues: Vec<String> =
                    p.eigenvalues.iter().map(|e| format!("{e:.4}")).collect();
                let verdict = match p.stable {
                    Some(true) => "stable (Lagrange–Dirichlet: a strict minimum of the potential)",
                    Some(false) => "unstable (a negative eigenvalue)",
                    None => "not decided (the Hessian is only semidefinite)",
                };
                section.paragraph(format!(
                    "Equilibrium {i} lies at the pole of {polar}, where {azimuth} moves nothing \
                     and M0 is singular. In the regular chart u = ({polar} − {polar}₀) cos \
                     {azimuth}, v = ({polar} − {polar}₀) sin {azimuth} the potential's Hessian \
                     has the eigenvalues {}: {verdict}.",
                    eigenvalues.join(", ")
                ));
            }
            if let (true, Some(m)) = (linearized, modes) {
                let frequencies: Vec<String> = m
                    .frequencies()
                    .iter()
                    .zip(&m.omega_squared)
                    .map(|(w, w2)| match w {
                        Some(w) => format!("ω = {w:.4} rad/s"),
                        None => format!("none (ω² = {w2:.4})"),
                    })
                    .collect();
                section.paragraph(format!(
                    "Equilibrium {i}, at the pole of {}: linearized in the regular chart ({}), \
                     natural frequencies {}.",
                    name(&m.polar),
                    m.chart.join(", "),
                    frequencies.join(", ")
                ));
            }
        }
    }
}

/// Where the first sentence of `paragraph` ends: the first `. ` not after an abbreviation (a
/// capitalised word of at most four letters or a single letter, as in a citation's
/// "Proc. R. Soc. A").
fn first_sentence_end(paragraph: &str) -> Option<usize> {
    paragraph.match_indices(". ").map(|(at, _)| at).find(|&at| {
        let word = paragraph[..at].rsplit(' ').next().unwrap_or("");
        let abbreviation = word.chars().next().is_some_and(char::is_uppercase)
            && word.chars().count() <= 4
            && word.chars().all(char::is_alphabetic);
        !abbreviation
    })
}

#[cfg(test)]
mod tests {
    use super::first_sentence_end;

    #[test]
    fn a_title_runs_past_a_citations_abbreviations() {
        let text = "The bicycle of Meijaard et al., Proc. R. Soc. A 463 (2007), with its Table 1. Four bodies.";
        let end = first_sentence_end(text).expect("a sentence end");
        assert_eq!(
            &text[..end],
            "The bicycle of Meijaard et al., Proc. R. Soc. A 463 (2007), with its Table 1"
        );
        assert_eq!(first_sentence_end("A pendulum. Swinging."), Some(10));
        assert_eq!(first_sentence_end("No end"), None);
    }
}
