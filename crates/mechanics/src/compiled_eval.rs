//! Expressions that a search or a scan evaluates thousands of times at numbers, compiled once
//! to a [`numeric::Tape`]: the free variables are the tape's first inputs, every other symbol
//! is fixed at its value. Walking the trees instead costs a hash-map lookup per symbol and a
//! recursion per node at every point.

use std::cell::RefCell;

use cas::{Expr, Symbol};
use numeric::{Tape, TapeError};

/// Compiled expressions with their buffers (reused between evaluations).
pub(crate) struct CompiledExprs {
    tape: Tape,
    /// The free variables' values, then the fixed symbols' values.
    inputs: RefCell<Vec<f64>>,
    registers: RefCell<Vec<f64>>,
    free: usize,
}

impl CompiledExprs {
    /// Compiles `exprs` with `free` as the variables and `known` fixed; any other symbol is
    /// looked up with `value`. `None` when a symbol has no value or the tape cannot hold an
    /// expression: the caller then evaluates the trees.
    pub(crate) fn new(
        exprs: &[Expr],
        free: &[Symbol],
        known: &[(Symbol, f64)],
        value: &dyn Fn(Symbol) -> Option<f64>,
    ) -> Option<CompiledExprs> {
        let mut symbols = free.to_vec();
        let mut inputs = vec![0.0; free.len()];
        for (s, v) in known {
            if !symbols.contains(s) {
                symbols.push(*s);
                inputs.push(*v);
            }
        }
        // Each unbound symbol is named by the compiler; at most one round per symbol.
        loop {
            match Tape::compile(exprs, &symbols) {
                Ok(tape) => {
                    let registers = RefCell::new(tape.registers());
                    return Some(CompiledExprs {
                        tape,
                        inputs: RefCell::new(inputs),
                        registers,
                        free: free.len(),
                    });
                }
                Err(TapeError::UnboundSymbol { name }) => {
                    let symbol = Expr::symbol(&name).as_symbol()?;
                    if symbols.contains(&symbol) {
                        // A name that does not read back as the symbol (a rate): no tape.
                        return None;
                    }
                    inputs.push(value(symbol)?);
                    symbols.push(symbol);
                }
                Err(_) => return None,
            }
        }
    }

    /// The values at the free variables `x`; `None` when one is not finite, as a tree's
    /// evaluation would be.
    pub(crate) fn eval(&self, x: &[f64]) -> Option<Vec<f64>> {
        let mut inputs = self.inputs.borrow_mut();
        inputs[..self.free].copy_from_slice(x);
        let mut out = vec![0.0; self.tape.output_count()];
        self.tape
            .eval(&inputs, &mut self.registers.borrow_mut(), &mut out);
        out.iter().all(|v| v.is_finite()).then_some(out)
    }

    /// The one expression's value at `x` (for a tape of one expression).
    pub(crate) fn eval_one(&self, x: &[f64]) -> Option<f64> {
        self.eval(x).and_then(|v| v.first().copied())
    }
}
