//! The motion played back (`pim_studies::playback`) on the SAE example: time 0 is the fitted
//! run-out's start (the pose at contact), the last pose its rest; the sedan's braking begins a
//! skid's length back at the answer's speed before braking and slows at the constant rate that
//! reaches its contact speed at contact; the SUV, without a skid, approaches for `APPROACH` at its contact velocity.
use pim_case::case::Case;
use pim_core::VehicleId;
use pim_studies::playback::{pose_at, tracks, APPROACH};
use std::path::Path;

#[test]
fn the_motion_runs_from_the_braking_through_contact_to_rest() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases/reconstruction_us.toml");
    let case = Case::from_text(
        &path.display().to_string(),
        &std::fs::read_to_string(&path).unwrap(),
    )
    .unwrap();
    let done = pim_studies::reconstruct::reconstruct(
        &case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
    )
    .unwrap();
    let best = done.outcome.best.as_ref().unwrap();
    let fitted = pim_studies::runout::fitted(&case, best, 0.02, false).unwrap();
    let dt = 0.04;
    let all = tracks(&done, best, &fitted, dt);
    assert_eq!(all.len(), 2);
    for t in &all {
        let run = &fitted.runouts[t.index];
        let zero = t.poses.iter().find(|(s, _)| *s == 0.0).unwrap().1;
        assert_eq!(
            (zero.x, zero.y, zero.heading),
            (run.start.x, run.start.y, run.start.heading)
        );
        let (end, rest) = *t.poses.last().unwrap();
        assert_eq!((end, rest), (run.time, run.rest));
        assert!(t
            .poses
            .windows(2)
            .all(|w| w[1].0 > w[0].0 && w[1].0 - w[0].0 <= dt + 1e-12));
        assert_eq!(pose_at(t, 1e9), run.rest);
        let phases = best.phases.iter().find(|p| p.vehicle == t.vehicle).unwrap();
        let (t0, first) = t.poses[0];
        let speed = |m: &pim_runout::Motion| m.vx.hypot(m.vy);
        // One step before contact, the speed at contact and one step's deceleration (that of
        // the braking from the speed before it to the speed at contact over the skid).
        let a = match (
            phases.before_braking,
            &done.input.reconstruction.skids[t.vehicle.index()],
        ) {
            (Some(v0), Some(s)) => (v0 * v0 - phases.contact.powi(2)) / (2.0 * s.distance),
            _ => 0.0,
        };
        let k = t.poses.iter().position(|(s, _)| *s == 0.0).unwrap();
        let (tau, before) = t.poses[k - 1];
        assert!((tau + dt).abs() < 1e-12);
        assert!((speed(&before) - (phases.contact + a * dt)).abs() < 1e-9);
        if t.vehicle == VehicleId::One {
            let skid = done.input.reconstruction.skids[0].as_ref().unwrap();
            let back = (first.x - zero.x).hypot(first.y - zero.y);
            println!(
                "sedan: braking {:.3} s over {back:.4} m from {:.3} m/s",
                -t0,
                speed(&first)
            );
            assert!(t.braking);
            assert!((back - skid.distance).abs() < 1e-9, "{back}");
            assert!((speed(&first) - phases.before_braking.unwrap()).abs() < 1e-9);
        } else {
            assert!(!t.braking);
            assert!((t0 + APPROACH).abs() < 1e-12);
            assert!((speed(&first) - phases.contact).abs() < 1e-9);
        }
    }
}
