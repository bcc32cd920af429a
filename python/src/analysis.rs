//! [`PyAnalysis`]: a `lagrange::Analysis` behind a Python class. Each method is one call of
//! the library; results cross as strings, JSON text (the schema of docs/json.md, which the
//! command line prints too) or NumPy arrays. Long work runs with the interpreter released,
//! so that other Python threads (a Dask worker's) go on meanwhile.

use std::path::PathBuf;

use lagrange::report::document::Document;
use lagrange::{parse_assignment, Analysis, Error, MethodName, SimulationOptions};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::errors::to_py;
use crate::rhs::Rhs;

/// A model and its analysis (`lagrange._native.Analysis`); immutable from Python: values are
/// set on a copy ([`PyAnalysis::with_values`]).
#[pyclass(module = "lagrange._native", name = "Analysis", frozen)]
pub(crate) struct PyAnalysis {
    pub(crate) inner: Analysis,
    /// The name errors are reported against: the file as given, or `<text>`.
    pub(crate) file: String,
}

/// Reads, checks and lowers a model file.
#[pyfunction]
pub(crate) fn load_file(py: Python<'_>, path: PathBuf) -> PyResult<PyAnalysis> {
    let file = path.display().to_string();
    let loaded = py.detach(|| Analysis::from_file(&path));
    loaded
        .map(|inner| PyAnalysis {
            inner,
            file: file.clone(),
        })
        .map_err(|e| to_py(py, &e, &file))
}

/// Reads, checks and lowers model text; errors name it `file` (default `<text>`).
#[pyfunction]
#[pyo3(signature = (text, file=None))]
pub(crate) fn load_text(py: Python<'_>, text: &str, file: Option<String>) -> PyResult<PyAnalysis> {
    let file = file.unwrap_or_else(|| "<text>".to_owned());
    Analysis::from_text(text)
        .map(|inner| PyAnalysis {
            inner,
            file: file.clone(),
        })
        .map_err(|e| to_py(py, &e, &file))
}

/// The parts of a solution handed to Python.
type SolutionParts = (
    String,
    String,
    String,
    String,
    String,
    Vec<(String, u8, String)>,
);

/// A simulation's result handed to Python: columns, rows, ending word, its sentence, the
/// time reached, accepted steps.
type SimulationParts<'py> = (
    Vec<String>,
    Bound<'py, PyArray2<f64>>,
    String,
    Option<String>,
    f64,
    u64,
);

/// A sweep's result handed to Python: the columns of a final row, the final rows (NaN where
/// a run failed), the steps, each run's ending word, and each run's error (`None` when it ran).
type SweepParts<'py> = (
    Vec<String>,
    Bound<'py, PyArray2<f64>>,
    Vec<u64>,
    Vec<String>,
    Vec<Option<String>>,
);

#[pymethods]
impl PyAnalysis {
    /// A copy with values set: `(name, value)` pairs, the value a number or text (a constant
    /// expression such as `pi/4`, or for an input a function of `t`).
    fn with_values(
        &self,
        py: Python<'_>,
        values: Vec<(String, Bound<'_, PyAny>)>,
    ) -> PyResult<PyAnalysis> {
        let mut copy = self.inner.clone();
        for (name, value) in values {
            let result = if let Ok(number) = value.extract::<f64>() {
                copy.set_value(&name, number)
            } else if let Ok(text) = value.extract::<String>() {
                parse_assignment(&format!("{name}={text}"))
                    .map_err(Error::from)
                    .and_then(|a| copy.set(&a))
            } else {
                return Err(PyTypeError::new_err(format!(
                    "the value of `{name}` must be a number or a string (an expression)"
                )));
            };
            result.map_err(|e| to_py(py, &e, &self.file))?;
        }
        Ok(PyAnalysis {
            inner: copy,
            file: self.file.clone(),
        })
    }

    /// The report's title.
    fn title(&self) -> String {
        self.inner.title()
    }

    /// The coordinates, in order.
    fn coordinates(&self) -> Vec<String> {
        self.inner.system().coordinates().to_vec()
    }

    /// The parameters and inputs by name, after the sets.
    fn values(&self, py: Python<'_>) -> PyResult<Vec<(String, f64)>> {
        self.inner.values().map_err(|e| to_py(py, &e, &self.file))
    }

    /// The initial state `(q, q̇)` from the model's `initial` values and the sets.
    fn initial_state(&self, py: Python<'_>) -> PyResult<Vec<f64>> {
        self.inner
            .initial_state()
            .map_err(|e| to_py(py, &e, &self.file))
    }

    /// The solution as `(title, markdown, latex document, text, document JSON, sections)`,
    /// each section `(title, level, markdown)`.
    fn solution(&self, py: Python<'_>) -> PyResult<SolutionParts> {
        let solution = py
            .detach(|| self.inner.solution(None))
            .map_err(|e| to_py(py, &e, &self.file))?;
        let document = &solution.document;
        let sections = document
            .sections
            .iter()
            .map(|s| {
                let alone = Document {
                    title: String::new(),
                    sections: vec![s.clone()],
                };
                (s.title.clone(), s.level, alone.to_markdown())
            })
            .collect();
        Ok((
            document.title.clone(),
            document.to_markdown(),
            document.to_latex(),
            document.to_text(),
            document.to_json().to_string(),
            sections,
        ))
    }

    /// The equations of motion as JSON (docs/json.md), expressions in SymPy syntax.
    fn equations_json(&self, py: Python<'_>) -> PyResult<String> {
        let equations = py
            .detach(|| self.inner.equations().cloned())
            .map_err(|e| to_py(py, &e, &self.file))?;
        Ok(lagrange::report::eom_json(self.inner.system(), &equations).to_string())
    }

    /// The equilibria as JSON, as `lagrange equilibria --format json` prints them.
    fn equilibria_json(&self, py: Python<'_>) -> PyResult<String> {
        let found = py.detach(|| self.inner.equilibria().map(|e| e.to_json().to_string()));
        found.map_err(|e| to_py(py, &e, &self.file))
    }

    /// The linearizations as JSON, as `lagrange linearize --format json` prints them.
    fn linearized_json(&self, py: Python<'_>) -> PyResult<String> {
        let found = py.detach(|| {
            self.inner
                .equilibria()
                .map(|e| e.linearized_json(None, None).to_string())
        });
        found.map_err(|e| to_py(py, &e, &self.file))
    }

    /// One simulation, every row kept.
    #[pyo3(signature = (t_end=None, method=None, t_start=None, rtol=None, atol=None,
        output_step=None, step=None, stop_when=None, through_contact_loss=false,
        max_steps=None, max_rows=None))]
    #[allow(clippy::too_many_arguments)] // Python keyword arguments, one per option.
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        t_end: Option<f64>,
        method: Option<&str>,
        t_start: Option<f64>,
        rtol: Option<f64>,
        atol: Option<f64>,
        output_step: Option<f64>,
        step: Option<f64>,
        stop_when: Option<String>,
        through_contact_loss: bool,
        max_steps: Option<u64>,
        max_rows: Option<u64>,
    ) -> PyResult<SimulationParts<'py>> {
        let options = SimulationOptions {
            method: method_named(method)?,
            t_start,
            t_end,
            rtol,
            atol,
            output_step,
            step,
            stop_when,
            record_when: Vec::new(),
            through_contact_loss,
            max_steps,
            max_rows,
        };
        let run = py
            .detach(|| self.inner.simulate(&options))
            .map_err(|e| to_py(py, &e, &self.file))?;
        let rows = table(py, &run.rows, run.columns.len())?;
        Ok((
            run.columns,
            rows,
            run.ending.word(),
            run.ending.sentence(run.t),
            run.t,
            run.stats.steps,
        ))
    }

    /// Runs with the values of `names` set to each row of `values`, on all cores, the
    /// equations derived once; options as [`PyAnalysis::simulate`]'s.
    #[pyo3(signature = (names, values, t_end=None, method=None, rtol=None, atol=None,
        stop_when=None, through_contact_loss=false, max_steps=None))]
    #[allow(clippy::too_many_arguments)] // Python keyword arguments, one per option.
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        names: Vec<String>,
        values: PyReadonlyArray2<'py, f64>,
        t_end: Option<f64>,
        method: Option<&str>,
        rtol: Option<f64>,
        atol: Option<f64>,
        stop_when: Option<String>,
        through_contact_loss: bool,
        max_steps: Option<u64>,
    ) -> PyResult<SweepParts<'py>> {
        let options = SimulationOptions {
            method: method_named(method)?,
            t_end,
            rtol,
            atol,
            stop_when,
            through_contact_loss,
            max_steps,
            ..SimulationOptions::default()
        };
        let values = values.as_array();
        if values.ncols() != names.len() {
            return Err(PyValueError::new_err(format!(
                "the grid has {} columns for {} names",
                values.ncols(),
                names.len()
            )));
        }
        let rows: Vec<Vec<f64>> = values.rows().into_iter().map(|r| r.to_vec()).collect();
        // A pool of this call's own, not rayon's global one: in a process forked after the
        // global pool started (a `ProcessPoolExecutor`'s worker), that pool has no threads
        // and its work would wait forever.
        let pool = rayon::ThreadPoolBuilder::new()
            .build()
            .map_err(|e| PyRuntimeError::new_err(format!("no threads for the sweep: {e}")))?;
        let (columns, results) = py
            .detach(|| {
                pool.install(|| {
                    let columns = self.inner.simulation(&options)?.columns();
                    let results = self.inner.sweep(&options, &names, &rows, &|| {})?;
                    Ok::<_, Error>((columns, results))
                })
            })
            .map_err(|e| to_py(py, &e, &self.file))?;
        let width = columns.len();
        let mut finals = Vec::with_capacity(results.len());
        let (mut steps, mut endings, mut errors) = (Vec::new(), Vec::new(), Vec::new());
        for result in results {
            match result {
                Ok(run) => {
                    finals.push(run.last);
                    steps.push(run.steps);
                    endings.push(run.ending.word());
                    errors.push(None);
                }
                Err(e) => {
                    finals.push(vec![f64::NAN; width]);
                    steps.push(0);
                    endings.push("error".to_owned());
                    errors.push(Some(e.render(&self.file, Default::default())));
                }
            }
        }
        Ok((columns, table(py, &finals, width)?, steps, endings, errors))
    }

    /// The compiled right-hand side at the current values (see [`Rhs`]).
    fn rhs(&self, py: Python<'_>) -> PyResult<Rhs> {
        Rhs::new(&self.inner).map_err(|e| to_py(py, &e, &self.file))
    }

    /// The model text, for pickling (`None` for a system built in code).
    fn source_text(&self) -> Option<String> {
        self.inner.source().map(|s| s.text.clone())
    }

    /// The name errors are reported against.
    fn file(&self) -> String {
        self.file.clone()
    }
}

/// A method by name (`dopri5`, `gauss`, `sdirk` and their aliases).
fn method_named(name: Option<&str>) -> PyResult<Option<MethodName>> {
    name.map(|n| {
        MethodName::parse(n).ok_or_else(|| {
            PyValueError::new_err(format!(
                "unknown method `{n}` (available: dopri5, dop853, gauss, sdirk)"
            ))
        })
    })
    .transpose()
}

/// Rows of equal length `width` as a 2-D array (`rows × width`).
fn table<'py>(
    py: Python<'py>,
    rows: &[Vec<f64>],
    width: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let mut flat = Vec::with_capacity(rows.len() * width);
    for row in rows {
        if row.len() == width {
            flat.extend_from_slice(row);
        } else {
            // A run that produced no row (it failed before its first) has an empty last row.
            flat.extend(std::iter::repeat_n(f64::NAN, width));
        }
    }
    PyArray1::from_vec(py, flat).reshape([rows.len(), width])
}
