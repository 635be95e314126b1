//! # pim-reconstruct: the three phases of a collision in one fit
//!
//! A reconstruction goes from what the scene and the vehicles give to the speeds: marks before
//! the impact and EDR speeds (pre-impact), the impact (Planar Impact Mechanics, fitted by
//! [`pim_fit`]), and each vehicle's run-out from separation to its rest position (simulated by
//! [`pim_runout`]). Units: SI (m, s, kg, rad), the natural frame (x, y counter-clockwise).
//!
//! ## The cost
//! The unknowns are PIM's coefficients `(e, mu, e_m)` and the twelve velocities
//! `U = (contact state, separation state)`, bound by PIM's six equations and its admissibility
//! (as in every fit of [`pim_fit`]). The cost is one chi-square:
//!
//! ```text
//! chi2 = sum_k (U_k - est_k)^2 / s_k^2 + sum_j (a_j . U - t_j)^2 / s_j^2     contact evidence
//!      + sum_v sum_i (r_vi(V_v) / s_vi)^2                                   each vehicle's scene
//! ```
//!
//! plus `sum_n (z_n(U))^2` for evidence that is not linear in the velocities
//! ([`StateEvidence`]: the crush energy against the energy the impact takes out), and
//! where `r_vi(V_v)` are the residuals of vehicle v's scene (rest position and heading, each
//! mark's distance from the path) against the run-out from its separation velocity `V_v`,
//! for a given count of full turns to rest. The contact evidence holds what is known at contact
//! (e.g. no lateral velocity and no yaw rate before the impact, an EDR speed); the separation
//! state may carry estimates too.
//!
//! ## The search
//! 1. **Each scene alone** ([`pim_runout::estimate`]): one candidate separation state per count
//!    of turns, and up to three other local minima of that count's scene within a chi-square
//!    of 25 of it, besides every one that meets the scene as well as its data expect
//!    ([`pim_runout::Candidate::alternatives`]: a scene often has several basins
//!    for one count, e.g. a car that spins out against one whose tyres turn it back, and the
//!    scene's own best may be the one the impact cannot reach). A rest heading is known only
//!    modulo a full turn; the scene alone rarely decides the count, the impact does. Every
//!    candidate and alternative is a start of its own.
//! 2. **A bound per combination of counts**: each scene linearised at its own candidate
//!    (`r + J (V - V0)`: the Jacobian by forward differences of run-outs integrated through
//!    the candidate's own steps, see [`pim_runout::inverse`]), and the cost minimised under
//!    the momentum balance alone (linear momentum and the angular momentum
//!    about the impact centre, which every impulse at C conserves whatever the coefficients:
//!    one linear solve, a lower bound of the linearised impact fit).
//! 3. **First points, then refinement.** Each combination, from the lowest bound, first gets
//!    its first point: the impact fitted to its scenes linearised at their starts (evidence
//!    not linear in the velocities, such as an EDR's speed, linearised at the impact fitted
//!    without it), the run-outs simulated from the separation states it gives (a chi-square
//!    evaluated, not predicted: an upper bound of the best). Where that step overshoots (the
//!    point lies more than [`Settings::refine_margin`] above what its linearised fit
//!    predicted), the start itself is evaluated too, the impact fitted with the separation
//!    state held there; where it is lower it is a second start of the combination, refined in
//!    the thorough search after every combination has had its first refinement, where it lies
//!    within the margin of the best found or the best found does not fit (a restart from an
//!    answer goes on from the lower of the two). A long run-out's linearisation can send the undamped step
//!    thousands of chi-square away from a start that costs a few tens (a steered car's 98 m
//!    run-out: 180.8 against 52.5; an ABS-braked car's 38 m run-out without marks, whose
//!    rest is three equations in its three unknowns: 8,531 from the truth itself, whose
//!    chi-square is 8.1), and a refinement accepts only steps that lower what it starts from;
//!    the step's own point is kept as a start too, since a scene's candidate far from the
//!    impact is often nearer an answer after it. These probes spend at most half the budget of
//!    work left. The combinations are then refined from their first points: the lowest bound
//!    first (where the linearisations hold, the relaxation's order is right), then in the order
//!    of their first points' chi-squares (where they do not hold, the bound says nothing and an
//!    evaluated cost is the only evidence; a crash of two long rolling run-outs was refused at
//!    199 with the true combination, the seventh-lowest bound, left unrefined after the six
//!    before it spent the budget; its first point was the third lowest, and it answers at
//!    0.83). Both the first points and the refinements take one start per combination of
//!    counts before any combination's second (a scene with five exact solutions for one count
//!    must not spend the budget before another combination is tried at all). Refinement is
//!    Gauss-Newton over the
//!    separation state, with the exact impact fit inside at every step: the scenes'
//!    linearised rows join the impact fit as linear evidence ([`pim_fit::Combination`]), the
//!    fit is solved exactly and globally (its certificate), the scenes are relinearised at its
//!    separation state, and so on; a step that does not lower the true chi-square (the
//!    run-outs simulated, not linearised) is damped by Marquardt's rows that hold the
//!    separation state near the current one (weight `lambda` times the diagonal of `J^T J`:
//!    1e-3, then ten times more at each failure; after a success `lambda` is kept near what
//!    the step needed, by Nielsen's rule, `lambda max(1/3, 1 - (2 rho - 1)^3)` with `rho` the
//!    gain over the linearised fit's, so that a curved valley is not overshot again and again
//!    by undamped steps). An accepted point's run-outs are differentiated where they stand
//!    ([`pim_runout::differentiate`]), only when the refinement goes on from it. A combination is refined unless its scenes alone
//!    already cost at least the best found (a bound, the impact only adding cost, where the
//!    scenes' own search found each count's minimum), its momentum
//!    bound lies more than [`Settings::refine_margin`] above the best found, or
//!    [`Settings::max_refined`] were refined already whose bounds held (a refinement that ends
//!    more than the margin above its own bound shows the linearisation, hence the order, does
//!    not hold there, and does not count); [`Outcome::tried`] says which. A
//!    first point that lies more than the margin above what its own linearised fit predicted
//!    says only that the scenes' candidates are far from the separation states the impact
//!    gives (the linearisation that chose it does not hold there, so it neither bounds the
//!    combination nor sets it aside): in the second search (step 4), while the best found does
//!    not fit (none yet, or a chi-square above its count of data), the refinement goes on from that point, which the
//!    impact reaches (a restart from the impact's side); once the best found fits, such a
//!    combination more than the margin above it is abandoned (its run-outs far from the scene
//!    are costly to follow, and it cannot beat an answer that fits by much). A refinement is
//!    also abandoned where a step fails while it lies more than the margin above the best. It
//!    stops converged when a step gains less than 1e-6 (1 + chi-square) or a trial lies within
//!    that of the current point (the step is lost in the run-outs' precision).
//!
//! 4. **A second search from a scatter** when the first answer fits poorly (its chi-square's
//!    probability below [`SCATTER_BELOW_P`], 0.05) or the first search found none. The first search
//!    takes the scenes' quick look ([`pim_runout::EstimateSettings::quick`]: each count from its
//!    first guess and its neighbours' answers, polished to a chi-square gain of 1e-6, on run-outs
//!    of tolerance 1e-6); the second searches each scene again, on run-outs of the full
//!    precision ([`Settings::runout`]), from every start, with every count also explored from a scatter of separation states over the yaw
//!    rates of road crashes (with a rest position, those whose run-outs end there, one per yaw
//!    rate from -10 to 10 rad/s on several branches, every state of a branch whose rest
//!    heading passes a count's heading a start of that count;
//!    [`pim_runout::EstimateSettings::scatter`]) and from where the first search's three
//!    lowest refinements ended, for their counts and the counts next to them (the impact's
//!    side of the scene: [`pim_runout::EstimateSettings::starts`]), and steps 1 to 3 repeated; the lower of the
//!    two answers is kept ([`Outcome::scattered`]). The two searches share one budget of work
//!    ([`Settings::refine_work`]): the first may spend half of it (one that refines many
//!    combinations far from their scenes, each with long and slow run-outs, must leave the
//!    second its turn), the second as much as the first did (at least half the budget), no
//!    more; one refinement may spend at most a
//!    third of a search's budget (one combination crawling along a curved valley must leave
//!    the others theirs: a crash whose first refinement spent the whole of it was refused at
//!    383 with the true combination, whose bound was the second lowest, never refined; it
//!    answers at 5.1). Only the second refines on from a first point far from its
//!    linearisation while the best found does not fit (step 3), and only there is a
//!    combination refined whatever its momentum bound while the best found does not fit (the
//!    bound is one of the linearised problem, not a proof); the first, a quick look, sets
//!    such a combination aside once something is found.
//!
//! 5. **Continuation before a refusal**: an answer the evidence would refuse is searched once
//!    more from the best combination's end: refined with the scene's standard deviations
//!    widened sixteen times (the impact and the contact evidence lead, the scene only pulls),
//!    then eight, four, two times and as given, each stage from the one before. A refinement
//!    that crawled along a curved valley of the full evidence, or stopped in a basin the
//!    contact evidence does not want, is led around it; the lower answer is kept. (Two cases
//!    whose vehicle 2 at contact differs by 0.1 ft once answered at 31.2 and 5,977; with the
//!    continuation at 31.2 and 31.7.) So are two more combinations, the lowest scenes alone
//!    first: those whose scenes alone cost less than a refusal's chi-square (the combination
//!    can still be answered), and those whose momentum bound lies more than the margin below
//!    the best while their refinement ended more than the margin above that bound: the first
//!    step overshot into a basin of its own (a crash refused at 203.7, its truth's chi-square
//!    21.9, whose true combination was bounded at 7.0 and set aside at 8,500, answers at 6.1).
//!    Every stage starts on the frictions the stage before ended on (a long run-out started
//!    again on the stated friction ends far from where it did). It spends what
//!    the two searches left of the one budget
//!    of work, and stops at a stage whose answer the evidence already refuses: narrowing the
//!    scene's deviations raises each scene term's weight and leaves the others, so the minimum
//!    can only rise, and the refusal stands.
//!
//! 6. **A last look before a refusal**, where a scene vehicle is steered: its scene searched
//!    again from a scatter whose grid of CG velocities is mapped at every quarter rad/s of yaw
//!    rate instead of every whole one, steps 1 to 5 repeated with a budget of half the whole,
//!    the lower answer kept. Steered front wheels hold a rolling car on a curve of radius
//!    `L / tan(delta)`, so its yaw rate stays near `v tan(delta) / L`; where the distance to
//!    the rest fixes the speed, the states that reach the rest share nearly one yaw rate, and
//!    their branch of the rest curve can be a closed loop between two whole yaw rates, which
//!    the scatter's planes never cross. A car steered once around on a 76 m run-out (the SUV
//!    of realistic crash 100788, its states at rest between -1 and 0 rad/s) was refused at
//!    11,834 (the truth's chi-square 24.8); it answers at 6.61, in 45 s instead of 20 s. It
//!    runs only where the answer would be refused, so no answer found before changes.
//!
//! 7. **An earlier answer** ([`reconstruct_from`]): the answer of the case before an edit or
//!    of a neighbouring case, refined on this one; the lower answer is kept.
//!
//! ## What is proven and what is the best found
//! At the answer, the coefficients and both velocity states are the certified global optimum
//! of the impact fit with the scenes linearised at the found separation state ([`Found`]'s
//! certificate). The separation state itself is a local minimum of the whole cost in its
//! combination's basin, found from the scenes' own candidates, not proven global; the counts
//! of turns are compared by their refined costs. Combinations within a chi-square of 1 of the best
//! ([`Outcome::within`]) are not decided by the evidence.
//!
//! Why the second search runs only where the first answer fits poorly (p below
//! [`POOR_FIT_P`]): a search that stops in a wrong basin reports more than the truth's
//! chi-square (the truth is one of the states searched over). A wrong basin is a wrong branch
//! of a scene's rest curve (another count of turns, or a spin its tyres turn back): its
//! separation velocities differ from the truth's by metres per second, and the momentum
//! balance, the other scene and the contact evidence then cost tens to thousands of chi-square,
//! not the few of a fit. On 200 simulated realistic crashes (locked, ABS-braked, free rolling,
//! steered and jammed wheels, run-outs by an independent model), run with the second search
//! wherever the first answer fit worse than its median, it ran on 128 and found a lower answer
//! on 64: on 61 the first answer's probability was below 1e-4 (chi-square 16 to 63,620), on
//! the other three the gain was 0.41, 1e-4 and 1e-4 (within the chi-square of 1 the evidence
//! does not decide), each first answer already below the truth's. An answer that fits is
//! therefore kept, and the scatter, which costs seconds, runs on the others (74 of the 200).
//! On 200 simulated crashes with run-outs of up to 80 m and two turns
//! (`tests/reconstruct/long_spins.rs`) a search from the scenes' own candidates alone
//! reported more than the truth's chi-square on 5 (4 of them refused as inconsistent); with the
//! second, on none. A refusal therefore says that none of the impacts and run-outs
//! *searched* reaches the evidence, never that none exists.
//!
//! ## The pose at contact
//! Where the vehicles met (impact points, headings, the crush surface, each run-out's start)
//! is an input of a reconstruction; where it is uncertain, [`fit_pose`] fits it as unknowns
//! with priors: the whole reconstruction refitted at each pose (variable projection) and the
//! pose moved by Levenberg-Marquardt, the counts of turns held (see [`fit_pose`]). That descent
//! can end in another basin of the pose than the truth's; [`screened_poses`] draws starts for
//! another descent from the priors.
//!
//! ## Intervals of the speeds at contact
//! [`profile_interval`] gives a vehicle's 90 % profile interval of its speed at contact: the
//! speeds whose lowest chi-square with that speed held lies within `chi2_1(0.90) = 2.71` of the
//! answer's. Each profile point is the answer refitted ([`redo`]) with a penalty pulling the
//! forward speed at contact toward a target; by the Lagrange argument its minimiser is the
//! constrained minimiser at the speed it reaches, so the profile there is exact (see the
//! `profile` module). In a linear fit it is the answer plus or minus 1.645 standard
//! deviations; where the run-outs bend the chi-square it follows it, where a parametric
//! bootstrap about one answer comes out too narrow (on 200 realistic crashes with rolling,
//! steered and jammed run-outs the profile intervals held the truth in 90.5 %, the bootstrap's
//! in 71 % of the first 50).
//!
//! ## Pre-impact
//! A mark of braking before contact over a distance `d` with a share `b` of the road friction
//! `mu` on a grade `beta` gives the speed where the braking began, `v0^2 = vc^2 + 2 a d` with
//! `a = g (mu b cos(beta) + sin(beta))` ([`Skid`]). An EDR speed recorded `t` seconds before
//! contact with a deceleration `a` between is evidence on the speed along the heading at contact,
//! `v_edr - a t` (a [`pim_fit::ObservationKind::SpeedAlongHeading`] observation of the contact
//! problem).

mod combos;
mod error;
mod friction_step;
mod from;
mod impact_fit;
mod looks;
mod outcome;
mod point;
mod pose;
mod pose_starts;
mod problem;
mod profile;
mod refine;
mod relax;
mod search;
mod stages;
mod work;

pub use error::{ReconstructError, Result};
pub use from::{reconstruct_from, refine_earlier, Earlier, EarlierState};
pub use outcome::{
    Contradiction, EvidenceTerm, Found, Outcome, Phases, SceneFit, Status, Tried, TriedCounts,
    INCONSISTENT_P,
};
pub use pose::{fit_pose, refit, residual_z, PoseFit, PoseStart, PoseUnknown};
pub use pose_starts::{screened_count, screened_poses, Screened, SCREENED_POSES};
pub use problem::{
    ContactResidual, ContactTerm, NonlinearEvidence, Reconstruction, RoadFriction, SceneVehicle,
    Settings, Skid, StateEvidence, POOR_FIT_P, REFINE_WORK, SCATTER_BELOW_P,
};
pub use profile::{
    profile_end, profile_interval, profile_point, profile_rise, ProfileEnd, ProfileInterval,
    ProfilePoint, PROFILE_LEVEL,
};
pub use search::{redo, refined_from};
pub use stages::{follow, reconstruct};
