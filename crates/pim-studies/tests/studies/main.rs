//! The studies: damage, hostile inputs, input forms, realistic scenes and their coverage, tyre marks and the observer. One test binary.
#[path = "../common/mod.rs"]
mod common;
#[path = "../mutate/mod.rs"]
mod mutate;

mod contact_pose;
mod damage;
mod fuzz_inputs;
mod input_forms;
mod playback;
mod realistic_measured;
mod realistic_profile;
mod realistic_scenes;
mod realistic_spread;
mod scene_coverage;
mod tyre_marks;
mod watch;
mod zones;
