//! The summary a finished `pendulum-fem run` prints.

use crate::run::RunSummary;

fn print_impacts(i: &crate::run::impacts::ImpactSummary) {
    let every = i
        .mean_interval
        .map_or(String::new(), |t| format!(", one every {t:.4} s on average"));
    println!("  impacts            {}{every} (events.csv)", i.count);
    let restitution = i.restitution.map_or("-".into(), |e| format!("{e:.3}"));
    let rebound = i
        .rebound_angle
        .map_or(String::new(), |r| format!("; rebound to {:.4} deg", r.to_degrees()));
    println!("  restitution        {restitution} (|omega| leaving / reaching the wall, mean){rebound}");
}

/// Prints the summary of a finished run: the mesh, the steps, the times, θ, the impacts or the
/// period, the stresses, the energy balance, the warnings and the files written.
pub fn print_summary(s: &RunSummary) {
    let deg = |x: f64| x.to_degrees();
    println!("pendulum-fem run finished");
    println!(
        "  mesh               {} triangles, {} nodes, {} unknowns",
        s.mesh_triangles, s.mesh_nodes, s.unknowns
    );
    println!("  steps              {}", s.steps);
    if let Some(last) = s.last_step {
        println!(
            "  time grid          time.end = {} s is not a multiple of time.dt: the last step was shortened to {last:.6e} s to end there",
            s.time_reached
        );
    }
    println!(
        "  Newton iterations  {} ({} cut-backs)",
        s.newton_iterations, s.cutbacks
    );
    println!(
        "  wall time          {:.3} s (mesh {:.3} s, set-up {:.3} s, steps {:.3} s)",
        s.seconds_total, s.seconds_mesh, s.seconds_setup, s.seconds_steps
    );
    println!(
        "  theta              final {:.4} deg, range [{:.4}, {:.4}] deg",
        deg(s.theta_final),
        deg(s.theta_range.0),
        deg(s.theta_range.1)
    );
    match (s.impacts, s.period) {
        // with a wall θ crosses zero only inside the impacts: no period, the impacts instead
        (Some(i), _) if i.count > 0 => print_impacts(&i),
        (_, Some(p)) => println!("  period estimate    {p:.6} s (zero crossings)"),
        (_, None) => println!("  period estimate    - (fewer than two zero crossings)"),
    }
    println!("  max von Mises      {:.4e} Pa", s.von_mises_max);
    if let Some((impacts, force)) = s.contact {
        println!("  wall               {impacts} impacts, largest contact force {force:.4e} N (events.csv)");
    }
    println!(
        "  energy error       {:.3e}: the total energy, less the torque's work, drifted by at most {:.3e} J of the {:.4e} J the run has available",
        s.energy_error,
        s.energy_error * s.energy_scale,
        s.energy_scale
    );
    if let Some((eta, t)) = s.error_estimate {
        println!(
            "  reduced body       largest error estimate {eta:.2e} at t = {t:.4} s (warns above {:.0e})",
            crate::reduced::WARNING_BOUND
        );
    }
    for w in &s.warnings {
        println!("  {w}");
    }
    println!("  writing outputs    {:.3} s of the wall time", s.seconds_outputs);
    println!("  results in         {}", s.out_dir.display());
    let (frames, others): (Vec<_>, Vec<_>) = s
        .files
        .iter()
        .partition(|f| f.parent().and_then(|p| p.file_name()).is_some_and(|n| n == "frames"));
    for f in others {
        println!("    {}", f.display());
    }
    if let (Some(first), Some(last)) = (frames.first(), frames.last()) {
        println!(
            "    {} … {} ({} ParaView frames)",
            first.display(),
            last.file_name().unwrap_or_default().to_string_lossy(),
            frames.len()
        );
    }
}
