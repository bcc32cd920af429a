//! The reference for issue 20's "within 1.3× of a hand-written kernel": the planar n-link
//! pendulum's `q̈` by the articulated-body algorithm written by hand for this one system (point
//! masses `m_i` on rods `l_i` at absolute angles, gravity as an upward acceleration of the
//! base), timed beside lagrange's compiled right-hand side of the same model in one process,
//! interleaved. `cargo run --release -p lagrange --example nlink_kernel -- N [CALLS] [kernel]`
//! prints `kernel_ns=… lagrange_ns=… ratio=… difference=…` (the largest `|q̈|` difference,
//! relative); with `kernel`, only the kernel runs (for callgrind: bench/compare/callgrind.sh).

use std::time::Instant;

use lagrange::{numeric, Analysis, SimulationOptions};

/// The n-link pendulum's buffers: per joint the projected inertia `U = Iᴬ S` (2), the pivot `D`,
/// the reduced force `u`, and the bias acceleration `c` (2).
struct Kernel {
    mass: Vec<f64>,
    length: Vec<f64>,
    gravity: f64,
    projected: Vec<[f64; 2]>,
    pivot: Vec<f64>,
    reduced: Vec<f64>,
    motion: Vec<[f64; 2]>,
    bias: Vec<[f64; 2]>,
}

impl Kernel {
    fn new(mass: Vec<f64>, length: Vec<f64>, gravity: f64) -> Kernel {
        let n = mass.len();
        Kernel {
            mass,
            length,
            gravity,
            projected: vec![[0.0; 2]; n],
            pivot: vec![0.0; n],
            reduced: vec![0.0; n],
            motion: vec![[0.0; 2]; n],
            bias: vec![[0.0; 2]; n],
        }
    }

    /// `q̈` at `(q, q̇)`: each joint's velocity is the point's `(ẋ, ẏ)`, so the transforms are
    /// identities and the articulated inertia is a symmetric 2×2 (three numbers).
    fn rhs(&mut self, q: &[f64], qd: &[f64], qdd: &mut [f64]) {
        let n = q.len();
        let (mut ixx, mut ixy, mut iyy) = (0.0, 0.0, 0.0);
        let (mut px, mut py) = (0.0, 0.0);
        for j in (0..n).rev() {
            let (sin, cos) = q[j].sin_cos();
            let l = self.length[j];
            let s = [l * cos, l * sin];
            let w2 = l * qd[j] * qd[j];
            let c = [-w2 * sin, w2 * cos];
            ixx += self.mass[j];
            iyy += self.mass[j];
            let u = [ixx * s[0] + ixy * s[1], ixy * s[0] + iyy * s[1]];
            let d = s[0] * u[0] + s[1] * u[1];
            let reduced = -(s[0] * px + s[1] * py) - (u[0] * c[0] + u[1] * c[1]);
            let step = reduced / d;
            px += ixx * c[0] + ixy * c[1] + u[0] * step;
            py += ixy * c[0] + iyy * c[1] + u[1] * step;
            ixx -= u[0] * u[0] / d;
            ixy -= u[0] * u[1] / d;
            iyy -= u[1] * u[1] / d;
            self.projected[j] = u;
            self.pivot[j] = d;
            self.reduced[j] = reduced;
            self.motion[j] = s;
            self.bias[j] = c;
        }
        // Gravity −g ŷ as the base accelerating upward at g.
        let mut a = [0.0, self.gravity];
        for (j, out) in qdd.iter_mut().enumerate().take(n) {
            let u = self.projected[j];
            let x = (self.reduced[j] - u[0] * a[0] - u[1] * a[1]) / self.pivot[j];
            a[0] += self.motion[j][0] * x + self.bias[j][0];
            a[1] += self.motion[j][1] * x + self.bias[j][1];
            *out = x;
        }
    }
}

fn model(n: usize) -> String {
    let coordinates: Vec<String> = (1..=n).map(|i| format!("th{i}")).collect();
    let mut text = format!(
        "coordinates {}\nparameters g = 9.81",
        coordinates.join(", ")
    );
    for i in 1..=n {
        text += &format!(", m{i} = 1, l{i} = 1");
    }
    text += "\nframe N\n";
    for i in 1..=n {
        let previous = if i > 1 {
            format!("P{} + ", i - 1)
        } else {
            String::new()
        };
        text += &format!(
            "point P{i} = {previous}l{i}*sin(th{i})*N.x - l{i}*cos(th{i})*N.y\nparticle P{i} mass m{i}\n"
        );
    }
    text + "gravity -g*N.y\ninitial th1 = 0.5\n"
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let n: usize = args
        .next()
        .ok_or("usage: nlink_kernel N [CALLS]")?
        .parse()?;
    let calls: u32 = args.next().map_or(Ok(200_000), |s| s.parse())?;
    let kernel_only = args.next().is_some_and(|a| a == "kernel");
    if n == 0 {
        return Err("N must be at least 1".into());
    }
    let analysis = Analysis::from_text(&model(n))?;
    let options = SimulationOptions {
        t_end: Some(10.0),
        ..SimulationOptions::default()
    };
    let mut simulation = analysis.simulation(&options)?;
    // The state Pinocchio's timer uses: every angle 0.3, every rate 0.1.
    let state: Vec<f64> = (0..2 * n).map(|i| if i < n { 0.3 } else { 0.1 }).collect();
    let mut kernel = Kernel::new(vec![1.0; n], vec![1.0; n], 9.81);
    let mut derivative = vec![0.0; 2 * n];
    let mut qdd = vec![0.0; n];
    let (mut best_kernel, mut best_lagrange) = (f64::INFINITY, f64::INFINITY);
    let mut q = state[..n].to_vec();
    for _ in 0..7 {
        let started = Instant::now();
        for k in 0..calls {
            // The angle varies so the work cannot be hoisted out of the loop.
            q[0] = state[0] + f64::from(k) * 1e-15;
            kernel.rhs(std::hint::black_box(&q), &state[n..], &mut qdd);
            std::hint::black_box(&qdd);
        }
        best_kernel = best_kernel.min(started.elapsed().as_secs_f64() / f64::from(calls));
        if kernel_only {
            continue;
        }
        let lagrange = simulation.with_rhs(|system| -> Result<f64, numeric::RhsError> {
            let started = Instant::now();
            for k in 0..calls {
                let t = f64::from(k) * 1e-9;
                system.rhs(t, std::hint::black_box(&state), &mut derivative)?;
                std::hint::black_box(&derivative);
            }
            Ok(started.elapsed().as_secs_f64() / f64::from(calls))
        })?;
        best_lagrange = best_lagrange.min(lagrange);
    }
    kernel.rhs(&state[..n], &state[n..], &mut qdd);
    let scale = qdd.iter().fold(1.0f64, |s, x| s.max(x.abs()));
    let difference = qdd
        .iter()
        .zip(&derivative[n..])
        .fold(0.0f64, |d, (a, b)| d.max((a - b).abs()))
        / scale;
    println!(
        "kernel_ns={:.1} lagrange_ns={:.1} ratio={:.2} difference={difference:.1e} tree={}",
        best_kernel * 1e9,
        best_lagrange * 1e9,
        best_lagrange / best_kernel,
        simulation.rhs_by_tree()
    );
    Ok(())
}
