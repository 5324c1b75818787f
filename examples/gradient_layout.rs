//! A layout optimiser that follows the gradients: Adam on the sum of the missing scores places
//! the bedroom of `layout_optimizer` (a bed, two nightstands and a desk in a 4 x 5 m room,
//! the same 27 goals), with the pairwise collision check's penetration depth as a penalty.
//!
//! Each step takes every goal's score and its gradient with respect to every object's
//! `(x, y, yaw)` (`sceneeval_relations::grad`, `LayoutChecks::contact`) and moves every
//! object; a start that has not placed every goal after 400 steps is replaced by a new random
//! layout. It stops as soon as every goal holds, prints the steps, starts and time it took and
//! the layout, and exits with failure if no layout was found within 20,000 steps.
//!
//! Run with `cargo run -p sceneeval-examples --example gradient_layout --release [-- SEED]`
//! (the random starts' seed, 1 by default).

#![allow(clippy::print_stdout)]

use std::process::ExitCode;
use std::time::Instant;

use sceneeval_examples::layout::{Descent, GOALS, Layout, LayoutError};

const MAX_STEPS: usize = 20_000;

fn optimise(seed: u64) -> Result<bool, LayoutError> {
    let start = Instant::now();
    let mut layout = Layout::new()?;
    let mut descent = Descent::new(&mut layout, seed)?;
    let solved = descent.run(&mut layout, MAX_STEPS)?;
    let elapsed = start.elapsed();
    let (steps, starts) = descent.work();
    println!(
        "gradient descent (Adam): {steps} steps ({} goal scores with gradients) from {starts} random starts in {:.3} s",
        steps * GOALS,
        elapsed.as_secs_f64()
    );
    if !solved {
        let (energy, poses) = descent.best();
        println!("no layout met every goal; the best had energy {energy:.4}");
        for (i, p) in poses.iter().enumerate() {
            layout.set(i, *p)?;
        }
    }
    println!();
    let (text, ok) = layout.report()?;
    println!("{text}");
    Ok(ok)
}

fn main() -> ExitCode {
    let seed = match std::env::args().nth(1).map(|a| a.parse::<u64>()) {
        None => 1,
        Some(Ok(seed)) => seed,
        Some(Err(e)) => {
            println!("gradient layout: the seed must be a whole number: {e}");
            return ExitCode::FAILURE;
        }
    };
    match optimise(seed) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            println!("gradient layout: {e}");
            ExitCode::FAILURE
        }
    }
}
