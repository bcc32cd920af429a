//! [`Rhs`]: the compiled right-hand side `(t, (q, q̇)) → (q̇, q̈)` of a model at set values,
//! the tape the library's own integrators run (crates/simulation), for SciPy's `solve_ivp`.
//!
//! A call reads the state in place from the NumPy array (no copy, no conversion of Python
//! floats) and writes the derivative straight into the one new array it returns: that array
//! is the only allocation a call makes on the Python side.

use lagrange::simulation::Simulation;
use lagrange::{Analysis, Error, SimulationOptions};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyArithmeticError, PyValueError};
use pyo3::prelude::*;

/// The right-hand side of one model at its values (`lagrange._native.Rhs`).
#[pyclass(module = "lagrange._native")]
pub(crate) struct Rhs {
    simulation: Simulation,
    /// The state's length, `2n`.
    dimension: usize,
}

impl Rhs {
    /// Compiles the equations of `analysis` with its current values. A model without an end
    /// time gets one for the preparation alone: `rhs` does not integrate.
    pub(crate) fn new(analysis: &Analysis) -> Result<Rhs, Error> {
        let mut options = SimulationOptions {
            through_contact_loss: true,
            ..SimulationOptions::default()
        };
        let simulation = match analysis.simulation(&options) {
            Err(Error::NoEndTime) => {
                options.t_end = Some(1.0);
                analysis.simulation(&options)?
            }
            other => other?,
        };
        let dimension = simulation.initial_state().len();
        Ok(Rhs {
            simulation,
            dimension,
        })
    }

    /// Writes the derivative at `(t, y)` into `dy`.
    fn eval(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> PyResult<()> {
        let result = self.simulation.with_rhs(|system| system.rhs(t, y, dy));
        result.map_err(|e| {
            PyArithmeticError::new_err(format!("the right-hand side fails at t = {t}: {e}"))
        })
    }

    fn check(&self, length: usize) -> PyResult<()> {
        if length == self.dimension {
            Ok(())
        } else {
            Err(PyValueError::new_err(format!(
                "the state has {length} entries; this model's has {} (the coordinates, then their rates)",
                self.dimension
            )))
        }
    }
}

#[pymethods]
impl Rhs {
    /// `dy/dt` at time `t` and state `y = (q, q̇)` (a float64 array of length 2n).
    fn __call__<'py>(
        &mut self,
        py: Python<'py>,
        t: f64,
        y: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.check(y.len()?)?;
        let out = PyArray1::<f64>::zeros(py, self.dimension, false);
        {
            let mut written = out.readwrite();
            let dy = written
                .as_slice_mut()
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            match y.as_slice() {
                Ok(state) => self.eval(t, state, dy)?,
                // A strided view (a column of a larger array): copied once.
                Err(_) => self.eval(t, &y.as_array().to_vec(), dy)?,
            }
        }
        Ok(out)
    }

    /// `dy/dt` for every row of `ys` (`k × 2n`) at time `t`.
    #[pyo3(signature = (ys, t=0.0))]
    fn batch<'py>(
        &mut self,
        py: Python<'py>,
        ys: PyReadonlyArray2<'py, f64>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let states = ys.as_array();
        self.check(states.ncols())?;
        let rows = states.nrows();
        let out = PyArray2::<f64>::zeros(py, [rows, self.dimension], false);
        {
            let mut written = out.readwrite();
            let dys = written
                .as_slice_mut()
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            let mut state = vec![0.0; self.dimension];
            for (row, dy) in states
                .rows()
                .into_iter()
                .zip(dys.chunks_exact_mut(self.dimension))
            {
                for (s, v) in state.iter_mut().zip(row.iter()) {
                    *s = *v;
                }
                self.eval(t, &state, dy)?;
            }
        }
        Ok(out)
    }

    /// How many tape instructions one evaluation runs.
    fn instructions(&self) -> usize {
        self.simulation.rhs_instructions()
    }

    /// The state's length, `2n`.
    fn __len__(&self) -> usize {
        self.dimension
    }
}
