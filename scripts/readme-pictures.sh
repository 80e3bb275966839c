#!/usr/bin/env bash
# Regenerates the README's pictures with bvhview itself.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bvhview=target/release/bvhview
$bvhview snapshot assets/walk.bvh -o docs/walk.png
$bvhview snapshot assets/walk.bvh --frame 10 --style both --fit --angle 0.6 -o docs/walk_sticks.png
$bvhview snapshot tests/oracle/inputs/xsens_seed002_crlf_trail.bvh -o docs/xsens_seed002.png
$bvhview snapshot tests/data/asf_amc/heiden_12.asf --motion tests/data/asf_amc/heiden_12_02_01.amc \
    --frame 150 --style sticks --fit --angle 0.5 --size 400x400 -o docs/cmu_walk.png
# The chapter's side by side: our snapshot and where it differs from the article's own picture.
$bvhview diff docs/xsens_seed002.png tests/oracle/refs/xsens_seed002_crlf_trail__f0__a10__600x600.png \
    -o docs/xsens_seed002_diff.png
# Skinning: the skinning tutorial's demo, and a generated skin on a BVH skeleton.
$bvhview skin-demo --bend 30,45 -o docs/skin_demo.png
$bvhview snapshot tests/data/bvh/bvh11_131_01.bvh --frame 400 --skin --fit --angle 1.2 --size 400x400 -o docs/skin_cmu.png
# An animation: the whole walk cycle as a GIF.
$bvhview snapshot assets/walk.bvh --frames 0..40 --style both --fit --angle 0.6 --size 240x240 -o docs/walk.gif
# The HUD (I, --hud) and the step view of the recursion (J, --step).
$bvhview snapshot assets/walk.bvh --frame 10 --fit --angle 0.6 --style both --hud -q -o docs/walk_hud.png
$bvhview snapshot assets/walk.bvh --frame 10 --fit --angle 0.6 --step 5 -q -o docs/walk_step.png
# The studio look, joint names, two takes side by side, and the studio look animated.
$bvhview snapshot assets/walk.bvh --frame 10 --look studio --style both -q -o docs/studio.png
$bvhview snapshot tests/data/fbx/bvhpython_test_freebvh.fbx --frame 20 --look studio --size 480x480 -q -o docs/fbx.png
$bvhview snapshot assets/walk.bvh --frame 10 --fit --angle 0.6 --style both --names -q -o docs/names.png
$bvhview snapshot assets/walk.bvh tests/data/bvh/bvhpython_test_freebvh.bvh \
    --frame 20 --look studio --style both --hud -q -o docs/two_takes.png
$bvhview snapshot tests/data/bvh/bvhpython_test_freebvh.bvh --frames 0..69 --look studio --style both \
    --size 300x300 -q -o docs/studio.gif
# Three takes in three units (CMU's, inches, centimetres) scaled to one height, and the HUD fitted
# to a small picture.
$bvhview snapshot tests/data/bvh/bvh11_131_01.bvh tests/data/bvh/opencollar_run.bvh \
    tests/data/bvh/bvhpython_test_freebvh.bvh --frame 30 --look studio --hud -q -o docs/three_units.png
$bvhview snapshot tests/data/bvh/animateddrawings_rokoko_jesse_dance.bvh --frame 500 --look studio \
    --hud --size 240x240 -q -o docs/hud_240.png
# Retargeting: a CMU walk with its retargeting onto the built-in smpl22 drawn one over
# the other (the smpl22 figure paler), so that one camera sees both from the same side.
retargeted=$(mktemp -d)
$bvhview retarget tests/data/bvh/bvhparser_walk_01.bvh --onto smpl22 -q -o "$retargeted/walk_smpl22.bvh"
$bvhview snapshot tests/data/bvh/bvhparser_walk_01.bvh "$retargeted/walk_smpl22.bvh" --overlay \
    --look studio --style sticks --frame 150 --angle 0.35 --size 600x520 -q -o docs/retarget.png
rm -r "$retargeted"
# Characters: each committed character, in the studio look, with a take on it.
$bvhview snapshot tests/data/characters/maya_kenney_character_7700_binary.fbx \
    --character tests/data/characters/maya_kenney_character_7700_binary.fbx --frame 12 \
    --look studio --size 400x400 -q -o docs/character_kenney.png
$bvhview snapshot tests/data/bvh/bvh11_131_01.bvh --character tests/data/characters/capsule_mixamo.fbx \
    --frame 60 --look studio --size 400x400 -q -o docs/character_capsule_walk.png
$bvhview snapshot tests/data/bvh/animateddrawings_rokoko_jesse_dance.bvh \
    --character tests/data/characters/capsule_mixamo.glb --frame 500 --look studio --size 400x400 -q \
    -o docs/character_capsule_dance.png
$bvhview snapshot tests/data/bvh/bvh11_131_01.bvh tests/data/bvh/bvhpython_test_freebvh.bvh \
    --character tests/data/characters/maya_kenney_character_7700_binary.fbx \
    --character tests/data/characters/capsule_mixamo.glb --frame 60 --look studio --size 600x400 -q \
    -o docs/character_two.png
