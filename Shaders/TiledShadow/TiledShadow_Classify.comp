#version 450
#extension GL_GOOGLE_include_directive : require

// TILED_SHADOW tile classification (document 000, "Denoiser shadows tile classification"):
//   1. local neighbourhood encoding: Gaussian-weighted mean of the 1-spp bits over a 17x17 window,
//      separable and computed from the bitmasks (popcounts of row windows), pixels outside the
//      image excluded; the samples are 0 or 1, so the variance is mean * (1 - mean);
//   2. disocclusion: the expected previous viewZ from the clip -> previous clip matrix, compared
//      with the stored one under a tolerance that grows at grazing angles;
//   3. reprojection: temporal moments, variance boost on short history, history clamped to the
//      neighbourhood where the neighbourhood changed (a still one keeps its history: next to a sharp
//      edge mean +- 0.5 sigma would exclude the truth), blend toward the current sample by history
//      length.
// Tiles whose 3x5-tile neighbourhood is uniformly lit or shadowed skip 2 and 3 (and the filter).
// The TS_SHADOW_DATA variant (TiledShadowSettings::isShadowDataInput) also reads IN_SHADOWDATA's
// penumbrae: shadows that the light's own move carried keep little history (TS_MOVING_*).
// Group: 16x16 pixels = 2x4 tiles; shared memory only, so any subgroup size works.

#include "Bindings.glsl"
#include "TiledShadow_Classify.resources.h"
#include "CommonFrame.glsl"
#include "TiledShadow_Common.glsl"
#include "ShadowMotion.glsl"

#define GROUP_SIZE 16
#define GROUP_TILES_X 2 // GROUP_SIZE / TS_TILE_W
#define GROUP_TILES_Y 4 // GROUP_SIZE / TS_TILE_H
#define RADIUS_MAX 8
// Tiles around the group that its pixels' neighbourhoods reach: 1 left and right, 2 up and down.
#define HALO_TILES_X 1
#define HALO_TILES_Y 2
#define REGION_TILES_X (GROUP_TILES_X + 2 * HALO_TILES_X)
#define REGION_TILES_Y (GROUP_TILES_Y + 2 * HALO_TILES_Y)
#define REGION_TILES (REGION_TILES_X * REGION_TILES_Y)
#if HALO_TILES_X != 1 || REGION_TILES_X != 4
#error "the tile classification reads a region row as one uvec4"
#endif
// Rows of horizontal sums: the group's rows plus RADIUS_MAX above and below.
#define SUM_ROWS (GROUP_SIZE + 2 * RADIUS_MAX)
// How fast history outside the clamp box loses samples, per squared standard error of the local mean.
#define TS_HISTORY_REJECTION 2.0
// The clamp starts when the local mean moved this many standard errors from its running mean
// (fully on 2 standard errors later; the history is then at most TS_CHANGING_HISTORY long); the
// running mean follows with this blend factor.
#define TS_CHANGE_THRESHOLD 1.0
#define TS_LOCAL_MEAN_ALPHA 0.1
// Least blend factor per unit of resampling blur (f.x (1 - f.x) + f.y (1 - f.y), f the fractional
// position of the history sample): sub-pixel motion resamples the history every frame, which
// would wash sharp shadows out over a long history.
#define TS_RESAMPLING_ALPHA 1.0
// Resampling blur above which the history counts as moved by a fraction of a pixel (camera or
// object motion): blurred at sharp shadows, a short history of it is no evidence of a hard edge.
#define TS_MOTION_RESAMPLING 0.02
// Depth tolerance of the outer ring of the 4x4 history footprint, relative to the inner 2x2's.
#define TS_OUTER_TOLERANCE 1.5
// A history taken from part of its bilinear footprint (under TS_PARTIAL_FOOTPRINT of it on this
// surface: a pixel that a silhouette just uncovered) comes from texels up to a pixel and a half away.
// Next to a hard shadow (TS_SHADOW_DATA: the 3x3's shadowed samples all under
// TS_HARD_ARRIVAL_PENUMBRA) those can lie across the edge: where that history's mean contradicts the
// sample by more than TS_PARTIAL_CONTRADICTION, the pixel counts as disoccluded. A camera sliding past
// a sphere under a 0.4-degree sun (a scene written to break it) had the floor beside the silhouette's
// trailing edge take the cast shadow's history, output 0.05-0.4 on a truth of 1 (FLIP 1.048x the
// input's at 128x128; 0.988x with this rule: Tests/ShadowDoNoHarmTests.cpp, "a sliding camera
// uncovers it beside a hard shadow"). Without the hardness test camera_rotation fell under
// the input's relMSE at 64x64 (a soft penumbra's partial history is still worth keeping).
#define TS_PARTIAL_FOOTPRINT 0.75
#define TS_PARTIAL_CONTRADICTION 0.9
// A 9x9 window whose adjacent pixels change value at least this often relative to binary noise of
// its mean is a penumbra (see ChangesRelativeToNoise).
#define TS_STRUCTURE 0.6
// History farther than this from the value of a uniform 5x5 window of bits is dropped.
#define TS_NEAR_CONTRADICTION 0.25
// A footprint holding a texel whose temporal mean is within this of 0 and one within this of 1
// straddles a hard shadow edge.
#define TS_HARD_EDGE 0.05
// Variance boost: below this many samples (more under sub-pixel motion) it starts from the spatial
// variance of the 3x3 bits, at most the posterior variance of the samples' mean; then from one
// sample's temporal variance. Without motion it is scaled by TS_BOOST_SCALE.
#define TS_SPATIAL_BOOST_SAMPLES 5.0
#define TS_SPATIAL_BOOST_SAMPLES_MOTION 8.0
#define TS_BOOST_SCALE 2.0
// Longest history while the neighbourhood changes (fully at clampAmount 1).
#define TS_CHANGING_HISTORY 4.0
// A shadowed sample whose history gives it a likelihood below TS_CONTRADICTION_WIDE, with
// TS_CONTRADICTION_WIDE_NEIGHBORS of the 8 neighbours shadowed, restarts its history (a soft shadow
// arrived). Under sub-pixel motion, below TS_CONTRADICTION with a shadowed neighbour, it is output
// as it is (a shadow aliased into view).
#define TS_CONTRADICTION 0.02
#define TS_CONTRADICTION_WIDE 0.15
#define TS_CONTRADICTION_WIDE_NEIGHBORS 4
// A neighbourhood whose running local mean was uniform (within this of 0 or 1) and moved by more
// than TS_GLOBAL_CHANGE (a light switched on) keeps TS_CLAMPED_SAMPLES of its clamped history.
#define TS_UNIFORM_BEFORE 0.02
#define TS_GLOBAL_CHANGE 0.2
#define TS_CLAMPED_SAMPLES 3.0
// A light switched off (or a large occluder arriving) over a still surface: the local mean drops by
// more than TS_GLOBAL_CHANGE at once and the pixel's 3x3 is dark. Its dark sample is output as it is,
// and the state keeps the history from before the drop (history, temporal mean, running local mean),
// its length less TS_HOLD_DECAY per frame, while the drop lasts and at least TS_HOLD_MIN_SAMPLES
// remain. When the light returns, the neighbourhood matches the kept local mean again and the history
// goes on where it stopped instead of restarting. The raw sample kept is the last one before the drop
// too: a settled texel's last sample is its value, and the dark ones of the frames off contradicted
// the lit area around a penumbra on the frame back (a restart, 0.97 for truth 0.5). (A lamp switched
// every 4 frames, toggling_light at 64x64: relMSE ratio 2.79 -> 3.83, FLIP 0.87x -> 0.65x the input's;
// every 2, 3 and 5 frames 2.21, 2.11, 2.37 -> 3.87, 3.44, 4.36.) The same rule holds a fast occluder's
// umbra, whose surface is seldom lit as before when the local mean returns: fast_occluder at 128x128
// 4.47 -> 4.25, at 64x64 2.19 -> 2.10.
#define TS_HOLD_DECAY 0.25
#define TS_HOLD_MIN_SAMPLES 1.0
// Moving lights (TS_SHADOW_DATA, Shaders/Include/ShadowMotion.glsl): a pixel whose 3x3 penumbra
// radii (IN_SHADOWDATA's, of the shadowed samples) are all under this many pixels, or that has no
// shadowed sample around, holds a hard shadow (SIGMA's hard shadows reach a kernel, 0.6 of the
// radius, under a pixel). 0.75: the moving lamp's self-shadows of mesh_character at 64x64 under the
// input's FLIP with the lit samples kept exact in the a-trous passes (README, "Moving lamps").
#define TS_MOVING_HARD_PENUMBRA 0.75
// The other pixels (soft shadows, left to the filter) keep at most a quarter of their penumbra radius
// of the light's motion in their history.
#define TS_MOVING_SOFT_RADII 0.25
// Where that is under a frame (the light moves the shadows by more than a quarter of a penumbra radius
// a frame) and the 3x3's penumbra radii are under TS_MOVING_NARROW_PENUMBRA pixels, the output is the
// samples' plus-shaped mean (the pixel's sample twice, its four edge neighbours once: a reach of a
// pixel, as wide as the penumbra), kept by the a-trous passes. Their reach, 7 pixels on one frame's
// samples with the variance boosted for a short history, smeared venetian_blinds' stripes, moved by
// a turning sun, into grey at 960x540 (FLIP 1.35x the input's; 0.96x with the plus mean). Wider
// penumbrae keep the filter: up to 2 pixels the moving lamps' relMSE ratios fell by a fifth at
// 128x128 (moving_light 2.74 -> 2.19), and without the boost by half.
#define TS_MOVING_NARROW_PENUMBRA 1.0
// Moving occluders (TS_SHADOW_DATA, ShadowMotion.glsl): each shadowed sample of the group and a border
// of this radius gets, once, into group shared memory, where its shadow lay in the previous frame
// (_NRD_ShadowMotion_OccluderDelta: its occluder's move relative to the surface, projected along the
// light onto it). Where one of a pixel's 5x5 moved more than TS_OCCLUDER_MOVED pixels:
// - a hard shadow (the 5x5's penumbrae all under NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA) keeps as
//   little history as a moving light's (movedKeep: under a frame, output as sampled). Its history is
//   not moved: one-pixel shadows of thin fast bars, taken from where the estimate put them, came out
//   lit (a scene written to break it: FLIP 1.34x -> 1.62x the input's at 64x64);
// - a soft one takes its history where the 5x5's mean says its shadow was, and keeps as many frames
//   as hold the uncertainty of that estimate (the 5x5's spread around the mean, plus TS_OCCLUDER_MODEL
//   of the motion) under TS_OCCLUDER_SOFT_RADII of its widest penumbra radius (softKeep); but where
//   the 5x5's penumbrae are all under NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA, a pixel whose 3x3
//   holds only hard ones, or whose 3x3 samples agree, is a hard shadow's (isNarrowAround).
// The 5x5 reaches the lit pixels a leg's shadow left, up to 2 pixels from it (the 3x3 took mesh_thin at
// 64x64 to 0.77 where the 5x5 took it to 0.96). A lit sample of isNarrowAround among shadowed ones
// (at most TS_NARROW_LIT_NEIGHBORS lit neighbours, or TS_THIN_SHADOW_NEIGHBORS two of which lie
// opposite through it: a line of light, the gap between two legs' shadows) is output as it is: the
// penumbrae around are under a pixel, so the sample is nearly exact, where the history is the
// shadows' that moved off and the filter takes from the shadows beside it (mesh_thin: lit samples of
// truth 0.5-1 between shadows came out at 0.2-0.6; FLIP 1.0053x -> 0.9932x the input's at 128x128,
// 1.021x -> 0.987x at 192x192). Lit penumbra noise beside a moving occluder's edge is output as it
// is too: moving_occluder's relMSE ratio 2.13 -> 1.58 at 64x64, 4.48 -> 4.30 at 256x256 (its FLIP
// lower at every size); with 3 lit neighbours, disocclusion at 64x64 fell under half the oracle's.
#define TS_NARROW_LIT_NEIGHBORS 2
#define TS_OCCLUDER_RADIUS 2
#define TS_OCCLUDER_MOVED 0.05
#define TS_OCCLUDER_MODEL 0.1
#define TS_OCCLUDER_SOFT_RADII 1.0
// Next to hard shadows that the light's move carried (a finite history kept, see movedKeep), the
// samples are exact but within a penumbra radius of an edge, which the boosted filter on the short
// history blurs: a shadowed sample of a hard penumbra (TS_HARD_ARRIVAL_PENUMBRA) and a lit one with
// at least TS_MOVING_LIT_NEIGHBORS lit neighbours (on the lit side of the edge) are output as they
// are. Under a slowly turning sun venetian_blinds' lit pixels next to a slat's shadow read 0.99.
#define TS_MOVING_LIT_NEIGHBORS 4
// A switch whose local mean rose by more than this starts from the 3x3 bits (see isSwitchedOn).
#define TS_SWITCHED_ON 0.5
// Temporal determinism: the raw samples of the 4x4 history footprint against this frame's at the same
// offsets from the nearest texel. Where they change at most TS_DETERMINISTIC times as often as
// independent binary noise of their mean would (at least TS_DETERMINISTIC_EVIDENCE changes expected),
// the samples are not noise: a sharp shadow (or fine shadow detail, or one that moves without
// motion vectors) whose 1-spp sample is exact; a pixel whose sample is also unchanged is output as
// it is, and its history takes it.
#define TS_DETERMINISTIC 0.25
#define TS_DETERMINISTIC_EVIDENCE 3.0
// A shadow that moved without motion vectors, in a still view: a texel of the 4x4 footprint whose raw
// samples were all equal over at least TS_SETTLED_SAMPLES frames (temporal mean within TS_SETTLED of
// 0 or 1) is settled. Where this frame's bits at the same offsets contradict at least
// TS_MOVED_CONTRADICTIONS settled texels, a shadowed pixel whose history is lit restarts from its
// sample; a lit pixel whose history is shadowed needs TS_MOVED_CONTRADICTIONS_LIT of them and
// TS_MOVED_LIT_NEIGHBORS lit neighbours (or 2 opposite each other through it). Fewer settled frames
// (3) followed the blinds better at 64x64 but made the moving shadows of the disocclusion scene at
// 256x256 unsteady.
#define TS_SETTLED 0.02
#define TS_SETTLED_SAMPLES 6.0
// A shadow that arrived without motion vectors, seen by the pixel itself in a still view: its sample
// was shadowed on this frame and the last, under a history whose temporal mean held at most that one
// shadowed sample (within TS_SETTLED of lit, over at least TS_SETTLED_SAMPLES samples), next to at
// least TS_PERSISTENT_NEIGHBORS shadowed neighbours. Binary noise of mean m gives two shadowed
// samples in a row after n lit ones with probability m^n (1 - m)^2, at most about 1% a frame for
// n = 6; the shadow restarts the pixel's history (see isPersistent). Lit samples under a settled
// shadow are left to the rules above: a false light in an umbra costs a hundred times more in
// relMSE, and the same test for them cost the still scenes up to 15% at 256x256.
#define TS_PERSISTENT_NEIGHBORS 1
// TS_SHADOW_DATA: a shadowed sample whose own penumbra radius (IN_SHADOWDATA) is under this many
// pixels is exact but within that distance of the shadow's edge (the lab's samples, like most
// engines', lie on the pixel centre or its jittered position). Such a sample in a still view
// - under a lit texel whose samples were all lit (TS_SETTLED), at least TS_HARD_ARRIVAL_SAMPLES of
//   them (not TS_SETTLED_SAMPLES: next to thin shadows that move, the changing neighbourhood keeps
//   the histories short; a thin bar's shadow arriving on such a texel was output at 0.84-0.92 on a
//   truth of 0), is output as it is: a hard shadow
//   arrived, or a pixel whose truth is nearly lit drew a shadowed sample; the first costs about a
//   hundred times more when mistaken (relMSE of a lit history on a dark truth), and is the common one
//   where a thin occluder moves (the spider's legs of mesh_thin, 1 to 2 pixels wide, with no
//   shadowed neighbour to pass TS_PERSISTENT_NEIGHBORS). The history goes on unchanged.
// - shadowed again on the next frame restarts like isPersistent's, without its shadowed neighbour.
// (Measured in Shaders/TiledShadow/README.md, "Hard shadows that arrive".)
#define TS_HARD_ARRIVAL_PENUMBRA 0.25
#define TS_HARD_ARRIVAL_SAMPLES 2.0
// Samples' worth of the history that a hard shadow output as sampled keeps (its sample), see movedKeep.
#define TS_MOVED_HARD_SAMPLES 4.0
// A shadowed sample of a hard penumbra (TS_HARD_ARRIVAL_PENUMBRA, above 0) on a history of fewer
// than TS_HARD_FRESH_SAMPLES samples, in a still view, is output as it is too: the history cannot yet
// tell a penumbra from a sharp shadow, and the boosted filter would light the umbrae that a
// disocclusion or a restart revealed (the corners of compact shadows, which the 3x3 pattern tests
// take for noise: disocclusion at 64x64). A penumbra of 0 (a light sample below the surface's
// horizon) is left out unless the whole light is below it (isBelowHorizon): fast_occluder's boxes
// have faces turned side-on to its sphere lamp, half of which is above their horizon, and lost 13-17%
// at 128x128 and 256x256 with them.
#define TS_HARD_FRESH_SAMPLES 2.0
// Under camera motion, a shadowed sample whose penumbra radius is above 0 and under this many pixels is
// output as it is whatever its history (resampled every frame, it greys a hard shadow's small parts:
// the contact shadows of mesh_engine's machine). Up to TS_HARD_ARRIVAL_PENUMBRA it gained more relMSE
// on the camera scenes at 64x64, but took camera_rotation above the input's FLIP at another seed (a
// pixel centre within a quarter-pixel penumbra is not exact). The lit side of such an edge: a lit
// sample with at least TS_MOVING_EXACT_LIT_NEIGHBORS lit neighbours, whose shadowed neighbours all
// have a penumbra radius above 0 and under TS_MOVING_EXACT_PENUMBRA (or lie below the light's horizon,
// AreShadowedNeighborsExact), is output as it is too, disoccluded or not. (4: the lit corner of a hard
// shadow's corner as well; with 5, a hard sun's box corners under a fast orbit lost 0.05-0.13 of their
// light, FLIP 1.02x the input's at 64x64. A box's lit face beside its face turned away from a 0.1-degree
// sun, under an orbit of 3.75 degrees a frame at 128x128: 0.67-0.98 for truth 1 from the disoccluded
// and the below-horizon neighbours left out, FLIP 1.089x the input's; 1.0034x with both.)
#define TS_MOVING_EXACT_PENUMBRA 0.1
#define TS_MOVING_EXACT_LIT_NEIGHBORS 4
// A disoccluded lit sample has no history, and the boosted filter, its only estimate, takes from the
// shadowed side of the edge: there the shadowed neighbours' penumbra radii may reach this many pixels.
// (A 0.1-degree sun under a camera orbiting 3.75 degrees a frame, 256x256: penumbrae of 0.09-0.11
// pixel, the lit strip that the orbit brings in at the image's left border output 0.53-0.98 for truth
// 1; FLIP 1.032x -> 1.020x the input's. Every built-in scene at 64x64 and 128x128 equal or lower FLIP.)
#define TS_DISOCCLUDED_EXACT_PENUMBRA 0.2
// An exact edge in a still view (TS_SHADOW_DATA): every shadowed sample of the 3x3 has a penumbra
// radius under TS_EXACT_EDGE_PENUMBRA pixels, or 0 with the whole light below its surface's horizon
// (a face turned away: the lab's, and any application's, occluder distance 0). The lit side of such an
// edge on a fresh history (TS_HARD_FRESH_SAMPLES, a light just switched on or moved) is output as
// sampled, as the shadowed side already is; after a switch both restart their history at the sample:
// started from the 3x3 mean (isSwitchedOn), the history of a lamp switched every 3 frames kept the lit
// pixels beside its hard shadows grey for the whole on-period (0.81-0.95 for truth 1; FLIP 1.53x the
// input's at 64x64, 0.96x with both rules). And while the history is younger than
// TS_TEMPORAL_ONLY_SAMPLES, no spatial filter there (the variance handed on is 0): the 1-spp samples
// of an exact edge are right but for the pixels the edge crosses, which the accumulation of jittered
// samples antialiases, while the boosted filter took light across the edge into narrow shadows and
// shade into narrow lit lines (a blind's stripes after its sun stopped: FLIP 1.08x the input's at 64x64,
// 0.89x; from the 8th sample on the filter is weak, and it keeps the relMSE of the penumbrae that an
// edge of half a pixel still has at 128x128: roughness_sweep 11.48 -> 8.44 without that limit).
#define TS_EXACT_EDGE_PENUMBRA 0.5
#define TS_TEMPORAL_ONLY_SAMPLES 8.0
#define TS_MOVED_CONTRADICTIONS 2
#define TS_MOVED_CONTRADICTIONS_LIT 3
#define TS_MOVED_LIT_NEIGHBORS 3
// A lit sample under a dark history whose whole 3x3 is lit on this frame and was on the last (the
// footprint's texels at the same offsets, at least TS_LIT_AREA_PAIRS of the 8 on this surface) is
// lit evidence too: the trailing side of a shadow that moved off without motion vectors, where its
// penumbra kept the texels from settling (moving_occluder). Binary noise of lit fraction m gives it
// with probability m^18; a shadow thinner than a pixel, whose neighbours are lit, still needs its own
// two samples and those of its neighbours along it lit (the lit sample alone on two frames took
// thin_geometry, a still scene, down 11% at 64x64; all 8 neighbours lit on this frame alone, 23%).
#define TS_LIT_AREA_PAIRS 6
// A light switched on over a dark neighbourhood (isSwitchedOn): a lit sample whose 3x3 bits are lit
// on less than this fraction (4 of 9 at most) is a dark penumbra's noise more often than not; its
// history starts from the running mean of the 3x3 mean (worth 3 samples) and the sample, a quarter
// of the way to the sample, instead of the blend toward the sample, which a young history makes
// nearly the sample (a lit sample in a mostly dark 3x3 costs most in relMSE). From 5 of 9 lit on, FLIP rose above the input's on
// toggling_light at 64x64 (seed 2).
#define TS_SWITCHED_ON_LIT_NEAR 0.5
// Lit stripes that keep moving without motion vectors (a blind under a turning sun seen at high
// resolution): the texels they pass over are lit one frame in several, so their temporal means stay
// between 0 and 1 and none is settled. A lit sample on a thin line of light (1 or 2 pixels wide:
// see HasThinLine) under a temporal mean below TS_STRIPE_MEAN of at least TS_STRIPE_SAMPLES samples,
// where at least TS_STRIPE_FLIPS texels of the 4x4 footprint changed value since the last frame and
// at most TS_STRIPE_SETTLED of them is settled, restarts from its sample like a lit pixel on settled
// texels. The limit on settled texels keeps a penumbra row beside a still lit line (a 2-pixel "line"
// of samples) from passing: without it thin_geometry (still) lost 19% at 64x64. See "Lit stripes
// that keep moving" in the README.
#define TS_STRIPE_MEAN 0.25
#define TS_STRIPE_SAMPLES 4.0
#define TS_STRIPE_FLIPS 4.0
#define TS_STRIPE_SETTLED 1
// In a still view, a shadowed pixel with at most this many shadowed neighbours, two of them opposite
// each other through it, is a thin shadow (see isSharpShadow).
#define TS_THIN_SHADOW_NEIGHBORS 3
// In a still view, a 5x5 window with at least this many isolated pixels in its inner 3x3 (see
// IsolatedPixels) is penumbra noise, whatever its 9x9 window looks like (see isSharpShadow).
#define TS_NOISE_ISOLATED 2u
// A dark pixel (blended result below TS_DARK_RESULT) in sharp structure is output as sampled while its
// history is shorter than TS_SHARP_SAMPLES: the variance boost of a short history would spread the
// light around it into the umbra (a light switched on again, a restarted history).
#define TS_SHARP_SAMPLES 8.0
#define TS_DARK_RESULT 0.1
// Least pixels of the 3x3 around a shadowed sample, on its surface in the previous frame, that the test
// of isExactShadow compares (a thin shadow cast by an object next to it has neighbours on that object).
#define TS_EXACT_PAIRS 5.0
// Under motion, an edge pixel whose 3x3 samples did not change (or once, in a 5x5 window without
// isolated pixels) and whose 4x4 footprint changed at most this many times is output as sampled (see
// isExactMoving). One change in the 3x3 anywhere, or 4 in the 4x4, helped at 64x64 but lost up to 11%
// of the relMSE ratio at 960x540, where penumbrae are several pixels wide and their samples change
// less often than that over their bright or dark parts.
#define TS_EXACT_MOVING_FLIPS 2.0
// Under motion, a sample whose blended result and temporal mean are both within TS_SETTLED_MOVING of
// it, over at least TS_SETTLED_MOVING_SAMPLES samples, is output as it is (see isSettledMoving).
#define TS_SETTLED_MOVING 0.02
#define TS_SETTLED_MOVING_SAMPLES 3.0
// Under motion, a pixel with a neighbour whose normal makes a cosine below this with its own (26
// degrees: a crease, a silhouette, detail finer than a pixel) takes its sample (see isTurned).
#define TS_TURNED_NORMAL_COS 0.9
// Under camera motion, a pixel whose 3x3 holds a shadowed sample with a penumbra radius wider than this
// many pixels (TS_SHADOW_DATA) lies in or beside a penumbra that the resolution resolves: its 1-spp
// sample is not exact, and isSharpShadow, isSettledMoving and isTurned, which output the sample as it
// is, leave it to the filter (see isWidePenumbra).
#define TS_WIDE_PENUMBRA 1.0
// Under camera motion (TS_SHADOW_DATA), a shadowed sample whose 3x3 bits look like penumbra noise
// (IsNoisyPattern) is sharp all the same where every shadowed sample of its 3x3 has a penumbra radius
// under this many pixels (or lies below its surface's horizon, see isBelowHorizon): so narrow a
// penumbra makes no such pattern; it is the occluder's outline (the corner of a two-pixel-wide pole's
// shadow under a hard sun). 0.25 took camera_rotation at 64x64 above the input's FLIP at another seed
// (1.0010x), as TS_MOVING_EXACT_PENUMBRA 0.25 did.
#define TS_NOISE_PENUMBRA 0.15
// Window radius of the "near" statistics (variance boost, clamp box extension).
#define TS_BOOST_RADIUS 1
// The image's outermost ring of pixels beside an exact edge (TS_SHADOW_DATA: every shadowed sample of
// its 3x3 inside the image has a penumbra radius under TS_EXACT_EDGE_PENUMBRA, as for the still view's
// exact edges, and one is there) hands the filter this fraction of its variance. Every pass's 3x3 taps
// lose a third of their weight there, the side outside the image, and the rest lies on one side of the
// pixel: next to an edge the weighted mean leans toward whatever the inner side holds. Under camera
// motion that ring is where new surface enters, with no history and so the strongest boost:
// mesh_engine's camera swing at 64x64 brought lit samples of truth 0.81-1 in beside a shadow's sharp
// edge at the left border, and the filter output them at 0.5-0.7 (FLIP 1.0028x the input's; 0.9986x
// with this, relMSE ratio 1.176 -> 1.142). In a wider penumbra the ring keeps its variance: the truncated
// window is not biased there, only narrower (scaled whatever the penumbra, the border of a uniform
// penumbra under camera motion had an RMS error of 0.149 against 0.127, TiledShadowTests). Other scales,
// on the whole ring: a quarter 0.9994x; a quarter on the two outermost rings 1.0011x; 0.1 of the
// filter's prefiltered variance instead 0.9992x.
#define TS_BORDER_VARIANCE 0.1

shared uint sMask[REGION_TILES];  // Bits of the region's tiles, pixels outside the image cleared.
// Per region row of REGION_TILES_X tiles, bit 0: the tile has a lit pixel in the image; bit 1: a
// shadowed one. One vector per row: a tile's 3x5 neighbourhood is five loads.
shared uvec4 sMixed[REGION_TILES_Y];
shared float sRowSum[SUM_ROWS * GROUP_SIZE];
shared uint sTileHasSurface[GROUP_TILES_X * GROUP_TILES_Y];
#if TS_SHADOW_DATA
// Where the shadow of each shadowed sample of the group and a border of TS_OCCLUDER_RADIUS lay in the
// previous frame (pixels from it, _NRD_ShadowMotion_OccluderDelta), and its penumbra radius (pixels;
// negative: lit, sky, or the occluder unknown).
#define OCCLUDER_REGION (GROUP_SIZE + 2 * TS_OCCLUDER_RADIUS)
shared vec2 sOccluderDelta[OCCLUDER_REGION * OCCLUDER_REGION];
shared float sOccluderPenumbra[OCCLUDER_REGION * OCCLUDER_REGION];
#endif

float MomentWeight(int i)
{
    vec4 w = i < 4 ? gMomentWeights0 : (i < 8 ? gMomentWeights1 : gMomentWeights2);
    return w[i & 3];
}

float MomentStep(int i)
{
    vec4 w = i < 4 ? gMomentSteps0 : (i < 8 ? gMomentSteps1 : gMomentSteps2);
    return w[i & 3];
}

// Bits of the 8 pixels of tile column 'tileX' in image row 'y' that lie inside the image.
uint RowValidBits(int tileX, int y)
{
    if (y < 0 || y >= int(gResourceSize.y) || tileX < 0)
        return 0u;
    int n = clamp(int(gResourceSize.x) - tileX * TS_TILE_W, 0, TS_TILE_W);
    return (1u << uint(n)) - 1u;
}

uint RowByte(uint mask, int row) { return (mask >> uint(TS_TILE_W * row)) & 0xFFu; }

// The 17 bits around column 'localX' (bit 8 = the column) of sum row 'row' (image row
// groupOrigin.y - RADIUS_MAX + row), from the region masks.
uint RowWindow(int row, int localX)
{
    int base = (row / TS_TILE_H) * REGION_TILES_X + localX / TS_TILE_W + HALO_TILES_X;
    int rowInTile = row % TS_TILE_H;
    uint window = RowByte(sMask[base - 1], rowInTile) | (RowByte(sMask[base], rowInTile) << 8) |
                  (RowByte(sMask[base + 1], rowInTile) << 16);
    return window >> uint(localX % TS_TILE_W);
}

// The 3x3 and 5x5 bits of NearWindow.
#define NEAR_3X3 0x739C0u
#define NEAR_5X5 0x1FFFFFFu
#if TS_BOOST_RADIUS != 1
#error "the near mean counts the 3x3 bits of NearWindow"
#endif

// In the layout of RowWindow: the bits of the 17 columns around 'localX' in sum row 'row' that are
// pixels of the image.
uint RowInImage(int row, int localX, ivec2 groupOrigin)
{
    int y = groupOrigin.y - RADIUS_MAX + row;
    if (y < 0 || y >= int(gResourceSize.y))
        return 0u;
    int x0 = groupOrigin.x + localX - RADIUS_MAX; // Column of bit 0.
    uint lo = uint(clamp(-x0, 0, 2 * RADIUS_MAX + 1));
    uint hi = uint(clamp(int(gResourceSize.x) - x0, 0, 2 * RADIUS_MAX + 1));
    return ((1u << hi) - 1u) & ~((1u << lo) - 1u);
}

// The 5x5 bits around the pixel at 'local': bit (dx + 2) + 5 (dy + 2) is pixel (dx, dy) away.
// 'inImage' gets the same bits for the pixels inside the image (all set away from the borders).
uint NearWindow(ivec2 local, ivec2 groupOrigin, bool isInterior, out uint inImage)
{
    uint bits = 0u;
    inImage = NEAR_5X5;
    for (int dy = -2; dy <= 2; dy++)
        bits |= ((RowWindow(local.y + RADIUS_MAX + dy, local.x) >> uint(RADIUS_MAX - 2)) & 0x1Fu) << uint(5 * (dy + 2));
    if (!isInterior)
    {
        inImage = 0u;
        for (int dy = -2; dy <= 2; dy++)
            inImage |= ((RowInImage(local.y + RADIUS_MAX + dy, local.x, groupOrigin) >> uint(RADIUS_MAX - 2)) & 0x1Fu)
                       << uint(5 * (dy + 2));
    }
    return bits;
}

// Whether lit pixels a and b of the 5x5 bits (bit x + 5 y) lie opposite each other through the
// centre on a line of light 1 pixel wide (p and q, the neighbours across the line, dark) or 2 pixels
// wide (one of them lit and the pixel beyond it, p2 or q2, dark).
bool IsLitLine(uint bits, uint a, uint b, uint p, uint q, uint p2, uint q2)
{
    bool isA = ((bits >> a) & 1u) != 0u, isB = ((bits >> b) & 1u) != 0u;
    bool isP = ((bits >> p) & 1u) != 0u, isQ = ((bits >> q) & 1u) != 0u;
    bool isP2 = ((bits >> p2) & 1u) != 0u, isQ2 = ((bits >> q2) & 1u) != 0u;
    return isA && isB && ((!isP && !isQ) || (!isP && isQ && !isQ2) || (isP && !isQ && !isP2));
}

// A thin line of light through the (lit) centre of the 5x5 bits, horizontal, vertical or diagonal,
// lit over the whole 5 pixels of the window: runs of 3 lit samples are common enough in wide
// penumbrae to cost the still scenes at 960x540 (grazing_floor -11%, sky -7% on the NVIDIA H200).
bool HasThinLine(uint bits)
{
    return (IsLitLine(bits, 11u, 13u, 7u, 17u, 2u, 22u) && (bits & 0x7C00u) == 0x7C00u) ||
           (IsLitLine(bits, 7u, 17u, 11u, 13u, 10u, 14u) && (bits & 0x421084u) == 0x421084u) ||
           (IsLitLine(bits, 6u, 18u, 8u, 16u, 4u, 20u) && (bits & 0x1041041u) == 0x1041041u) ||
           (IsLitLine(bits, 8u, 16u, 6u, 18u, 0u, 24u) && (bits & 0x111110u) == 0x111110u);
}

// Whether some two neighbours opposite each other through the centre are both set in 'bits' (5x5
// bits in the layout of NearWindow).
bool HasLine(uint bits)
{
    return ((bits >> 11) & (bits >> 13) & 1u) != 0u || ((bits >> 7) & (bits >> 17) & 1u) != 0u ||
           ((bits >> 6) & (bits >> 18) & 1u) != 0u || ((bits >> 8) & (bits >> 16) & 1u) != 0u;
}

// The 3x3 bits around a shadowed pixel that hold 3 or 4 other shadowed pixels, none of them
// opposite another through the centre, look like penumbra noise; fewer, more, or a line through
// the centre look like the sharp edge or thin shadow they are.
bool IsNoisyPattern(uint near)
{
    int count = 8 - bitCount(near & NEAR_3X3);
    return (count == 3 || count == 4) && !HasLine(~near);
}

// Pixels of the inner 3x3 of the 5x5 bits 'near' (layout of NearWindow) that differ from at least 3
// of their 4 neighbours ('inImage': neighbours outside the image do not count). Binary noise of mean
// 0.5 gives about 3 such pixels (a pixel differs from each neighbour with probability 0.5); a sharp
// edge, a corner or a thin line none (the end of a line one).
uint IsolatedPixels(uint near, uint inImage)
{
    uint isolated = 0u;
    for (int y = 1; y <= 3; y++)
    {
        for (int x = 1; x <= 3; x++)
        {
            uint bit = uint(5 * y + x);
            uint centre = (near >> bit) & 1u;
            uint differing = 0u;
            for (int k = 0; k < 4; k++)
            {
                uint neighbor = k == 0 ? bit - 1u : (k == 1 ? bit + 1u : (k == 2 ? bit - 5u : bit + 5u));
                differing += ((inImage >> neighbor) & 1u) & (((near >> neighbor) & 1u) ^ centre);
            }
            isolated += differing >= 3u ? 1u : 0u;
        }
    }
    return isolated;
}

// Binary noise of mean m changes value between two adjacent pixels with probability 2 m (1 - m); a
// sharp shadow edge or a thin shadow changes value along its outline only. Returns the changes
// between the adjacent pixels of the 9x9 window around 'local' relative to what noise of the
// window's mean would give (1 for noise, near 0 for an edge; 1 for a uniform window). Only pixels
// and pairs inside the image count.
float ChangesRelativeToNoise(ivec2 local, ivec2 groupOrigin, bool isInterior)
{
    uint previous = 0u, previousIn = 0u;
    uint changes = 0u, lit = 0u, pixels = 0u, pairs = 0u;
    for (int dy = -4; dy <= 4; dy++)
    {
        int row = local.y + RADIUS_MAX + dy;
        uint bits = (RowWindow(row, local.x) >> 4u) & 0x1FFu;
        uint inside = isInterior ? 0x1FFu : (RowInImage(row, local.x, groupOrigin) >> 4u) & 0x1FFu;
        uint horizontal = inside & (inside >> 1) & 0xFFu;
        changes += bitCount((bits ^ (bits >> 1)) & horizontal) + bitCount((bits ^ previous) & inside & previousIn);
        pairs += bitCount(horizontal) + bitCount(inside & previousIn);
        lit += bitCount(bits & inside);
        pixels += bitCount(inside);
        previous = bits;
        previousIn = inside;
    }
    float m = float(lit) / float(max(pixels, 1u));
    float expected = float(pairs) * 2.0 * m * (1.0 - m);
    return expected > 0.0 ? float(changes) / expected : 1.0;
}

// Sum over i in [-8, 8] of w(|i|) * bit(center + i) for the 17 bits of 'window' (center at bit 8):
// nested windows of half-width k weighted by w(k) - w(k + 1), one popcount each.
float WeightedRowSum(uint window)
{
    float sum = 0.0;
    for (int k = 0; k <= RADIUS_MAX; k++)
    {
        uint nested = ((2u << uint(2 * k)) - 1u) << uint(RADIUS_MAX - k);
        sum += MomentStep(k) * float(bitCount(window & nested));
    }
    return sum;
}

#if TS_SHADOW_DATA
// Whether the whole light lies below the horizon of the surface at view-space position Xv, normal Nv
// (the disk's fraction above it under 1e-4, not 0: asin(-1) need not be exactly -pi / 2); false where
// the light is not known.
bool IsLightBelowHorizon(vec3 Xv, vec3 Nv)
{
    float fraction = _NRD_ShadowMotion_HorizonVisibility(Xv, Nv); // -1: the light is not known.
    return fraction >= 0.0 && fraction < 1e-4;
}

// IsLightBelowHorizon at pixel q.
bool IsBelowHorizon(ivec2 q)
{
    float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
    vec3 N = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_Normal, gNearestClamp), q, 0)).xyz;
    return IsLightBelowHorizon(_NRD_ViewPosition(_NRD_PixelUv(q), z), N * mat3(gViewToWorld));
}

// The shadowed samples of the 3x3 around 'pixel' (the bits of 'near' clear; outside the image,
// clamped to its border) whose penumbra radius in pixels lies strictly between 'above' and 'below'
// (.x), and the others (.y; NaN among them).
uvec2 ShadowedPenumbrae3x3(uint near, ivec2 pixel, float above, float below)
{
    uvec2 counts = uvec2(0u);
    for (int i = 0; i < 9; i++)
    {
        if (((near >> uint((i / 3 + 1) * 5 + i % 3 + 1)) & 1u) != 0u)
            continue; // Lit.
        ivec2 q = clamp(pixel + ivec2(i % 3 - 1, i / 3 - 1), ivec2(0), ivec2(gResourceSize) - 1);
        float p = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), q, 0).y * gProjectY;
        bool isInside = p > above && p < below;
        counts += uvec2(isInside ? 1u : 0u, isInside ? 0u : 1u);
    }
    return counts;
}

// Whether the 3x3 around 'pixel' (the bits of 'near') holds no shadowed sample but exact ones: a
// penumbra radius in (0, 'below') pixels, or 0 with the whole light below that surface's horizon where
// the pixel's own surface (view-space position Xv, normal Nv) sees the whole light above its own (next
// to a sphere's terminator the pixel is a partly lit one: camera_translation at 64x64 lost 8% of its
// relMSE ratio without that test).
bool AreShadowedNeighborsExact(uint near, ivec2 pixel, float below, vec3 Xv, vec3 Nv)
{
    bool isCentreTested = false;
    for (int i = 0; i < 9; i++)
    {
        if (((near >> uint((i / 3 + 1) * 5 + i % 3 + 1)) & 1u) != 0u)
            continue; // Lit.
        ivec2 q = clamp(pixel + ivec2(i % 3 - 1, i / 3 - 1), ivec2(0), ivec2(gResourceSize) - 1);
        float p = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), q, 0).y * gProjectY;
        if (p > 0.0 && p < below)
            continue;
        if (p != 0.0 || !IsBelowHorizon(q))
            return false;
        if (!isCentreTested)
        {
            float fraction = _NRD_ShadowMotion_HorizonVisibility(Xv, Nv);
            if (!(fraction > 1.0 - 1e-4))
                return false;
            isCentreTested = true;
        }
    }
    return true;
}
#endif

// Mean of the 5x5 window's bits 'near' (row-major, the pixel at bit 12) over a plus around the pixel:
// the pixel twice, its four edge neighbours once, those outside the image ('inImage') left out.
float PlusMean(uint near, uint inImage)
{
    float sum = 2.0 * float((near >> 12u) & 1u), weight = 2.0;
    for (uint k = 0u; k < 4u; k++)
    {
        uint bit = k == 0u ? 7u : (k == 1u ? 11u : (k == 2u ? 13u : 17u));
        if (((inImage >> bit) & 1u) == 0u)
            continue;
        sum += float((near >> bit) & 1u);
        weight += 1.0;
    }
    return sum / weight;
}

// 'alpha * difference', at least TS_MIN_STEP (or all of the difference if smaller): the history is
// stored as fp16 and 12-bit unorm, where a small step would round back to the old value and stall
// a few thousandths short of a uniform signal.
#define TS_MIN_STEP (1.0 / 1024.0)
float StepToward(float difference, float alpha)
{
    float step = alpha * difference;
    return abs(step) < TS_MIN_STEP ? sign(difference) * min(abs(difference), TS_MIN_STEP) : step;
}

// Previous uv of the surface point at 'uv' (view-space position Xv, motion vector mv) and the viewZ
// expected there (.z): the camera motion through the reprojection matrix, plus the object's own
// motion (world-space vectors), or the uv motion of 2D vectors (their depth change is unknown: the
// camera-only depth is expected).
vec3 PreviousUv(vec2 uv, vec3 Xv, vec3 mv)
{
    vec4 clipPrev = gClipToClipPrev * (gViewToClip * vec4(Xv, 1.0));
    if (gMotionVectorScale.w != 0.0)
        clipPrev += gWorldToClipPrev * vec4(mv * gMotionVectorScale.xyz, 0.0);
    vec2 uvPrev = clipPrev.w > NRD_EPS ? (clipPrev.xy / clipPrev.w) * 0.5 + 0.5 : vec2(-1.0);
    if (gMotionVectorScale.w == 0.0 && (gMotionVectorScale.x != 0.0 || gMotionVectorScale.y != 0.0))
        uvPrev = uv + mv.xy * gMotionVectorScale.xy;
    return vec3(uvPrev, clipPrev.w);
}

void main()
{
    uint threadIndex = gl_LocalInvocationIndex;
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    ivec2 groupOrigin = ivec2(gl_WorkGroupID.xy) * GROUP_SIZE;
    ivec2 groupTile = ivec2(gl_WorkGroupID.xy) * ivec2(GROUP_TILES_X, GROUP_TILES_Y);
    ivec2 tileCount = ivec2(_TS_TileCount(gResourceSize));
    ivec2 pixel = groupOrigin + local;
    bool isInside = all(lessThan(pixel, ivec2(gResourceSize)));
    // Every pixel the group's neighbourhoods reach is inside the image: no border bookkeeping.
    bool isInterior = all(greaterThanEqual(groupOrigin, ivec2(RADIUS_MAX))) &&
                      all(lessThanEqual(groupOrigin + GROUP_SIZE + RADIUS_MAX, ivec2(gResourceSize)));

    // Masks of the group's tiles and their neighbours, pixels outside the image cleared.
    if (threadIndex < REGION_TILES)
    {
        ivec2 tile = groupTile + ivec2(threadIndex % REGION_TILES_X, threadIndex / REGION_TILES_X) -
                     ivec2(HALO_TILES_X, HALO_TILES_Y);
        uint valid = 0u, bits = 0u;
        if (all(greaterThanEqual(tile, ivec2(0))) && all(lessThan(tile, tileCount)))
        {
            for (int y = 0; y < TS_TILE_H; y++)
                valid |= RowValidBits(tile.x, tile.y * TS_TILE_H + y) << uint(TS_TILE_W * y);
            bits = texelFetch(usampler2D(gIn_Mask, gNearestClamp), tile, 0).x & valid;
        }
        sMask[threadIndex] = bits;
        sMixed[threadIndex / REGION_TILES_X][threadIndex % REGION_TILES_X] = (bits != 0u ? 1u : 0u) | (bits != valid ? 2u : 0u);
    }
    if (threadIndex < GROUP_TILES_X * GROUP_TILES_Y)
        sTileHasSurface[threadIndex] = 0u;

    float viewZ = isInside ? texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x : 0.0;
    bool isSky = !isInside || _NRD_IsSky(viewZ);
    uint localTile = uint(local.y / TS_TILE_H) * GROUP_TILES_X + uint(local.x / TS_TILE_W);
    barrier();

    if (!isSky)
        atomicOr(sTileHasSurface[localTile], 1u);

    // The tile is uniform when its 3x5-tile neighbourhood has only lit or only shadowed pixels.
    ivec2 regionTile = ivec2(local.x / TS_TILE_W + HALO_TILES_X, local.y / TS_TILE_H + HALO_TILES_Y);
    // (regionTile.x is 1 or 2: its row neighbours are tiles 0..2 or 1..3 of the row.)
    uint mixed = 0u, regionMixed = 0u;
    for (int y = 0; y < REGION_TILES_Y; y++)
    {
        uvec4 row = sMixed[y];
        uint rowMixed = row.x | row.y | row.z | row.w;
        regionMixed |= rowMixed;
        if (abs(y - regionTile.y) <= HALO_TILES_Y)
            mixed |= row.y | row.z | (regionTile.x == 1 ? row.x : row.w);
    }
    bool isSkipping = (gFlags & TS_FLAG_TILE_SKIPPING) != 0u;
    uint tileClass = TS_TILE_FILTERED;
    if (isSkipping && mixed != 3u)
        tileClass = (mixed & 1u) != 0u ? TS_TILE_LIT : TS_TILE_SHADOWED;

    // 1. Local neighbourhood, horizontal part: weighted sums of the rows the group's columns need
    // (skipped when the whole region is uniform, so that no tile of the group is filtered).
    bool needsMoments = gDebugView == TS_DEBUG_LOCAL_MEAN || !isSkipping || regionMixed == 3u;
    if (needsMoments)
    {
        for (uint entry = threadIndex; entry < SUM_ROWS * GROUP_SIZE; entry += GROUP_SIZE * GROUP_SIZE)
        {
            sRowSum[entry] = WeightedRowSum(RowWindow(int(entry) / GROUP_SIZE, int(entry) % GROUP_SIZE));
        }
#if TS_SHADOW_DATA
        for (uint entry = threadIndex; entry < OCCLUDER_REGION * OCCLUDER_REGION; entry += GROUP_SIZE * GROUP_SIZE)
        {
            ivec2 q = groupOrigin - TS_OCCLUDER_RADIUS + ivec2(int(entry % OCCLUDER_REGION), int(entry / OCCLUDER_REGION));
            vec2 delta = vec2(0.0);
            float penumbra = -1.0;
            if (all(greaterThanEqual(q, ivec2(0))) && all(lessThan(uvec2(q), gResourceSize)))
            {
                float p = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), q, 0).y;
                float zq = p >= 0.0 && p < NRD_FP16_MAX * 0.75 ? texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x : 0.0;
                if (!_NRD_IsSky(zq)) // Shadowed samples of a surface (NaN and lit read as lit).
                {
                    float pixels = min(p * gProjectY, NRD_FP16_MAX);
                    vec3 Nq = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_Normal, gNearestClamp), q, 0)).xyz * mat3(gViewToWorld);
                    if (_NRD_ShadowMotion_OccluderDelta(q, zq, Nq, pixels, delta))
                        penumbra = pixels;
                }
            }
            sOccluderDelta[entry] = delta;
            sOccluderPenumbra[entry] = penumbra;
        }
#endif
    }
    barrier();

    if (tileClass == TS_TILE_FILTERED && sTileHasSurface[localTile] == 0u)
        tileClass = TS_TILE_SKY;

    // Tile classes and counters (TILED_SHADOW_COUNTERS_* in NRDSettings.h), by each tile's first pixel.
    if (local.x % TS_TILE_W == 0 && local.y % TS_TILE_H == 0 && isInside)
    {
        ivec2 tile = pixel / ivec2(TS_TILE_W, TS_TILE_H);
        imageStore(gOut_TileClass, tile, uvec4(tileClass, 0u, 0u, 0u));
        uint slot = gCounterSlot * 4u;
        if (tileClass == TS_TILE_LIT || tileClass == TS_TILE_SHADOWED)
            atomicAdd(gCounters[slot + 0u], 1u);
        else if (tileClass == TS_TILE_SKY)
            atomicAdd(gCounters[slot + 1u], 1u);
    }
    if (threadIndex == 0u && gl_WorkGroupID.x == 0u && gl_WorkGroupID.y == 0u)
    {
        uint slot = gCounterSlot * 4u, other = (1u - gCounterSlot) * 4u;
        gCounters[slot + 2u] = uint(tileCount.x * tileCount.y);
        gCounters[slot + 3u] = gMethodFrame;
        for (uint i = 0u; i < 4u; i++)
            gCounters[other + i] = 0u;
    }

    if (!isInside)
        return;

    // 1. Local neighbourhood, vertical part, normalized by the weight of the pixels in the image.
    float localMean = 0.0;
    if (needsMoments && (tileClass == TS_TILE_FILTERED || gDebugView == TS_DEBUG_LOCAL_MEAN))
    {
        float sum = 0.0;
        for (int i = -RADIUS_MAX; i <= RADIUS_MAX; i++)
            sum += MomentWeight(abs(i)) * sRowSum[(local.y + RADIUS_MAX + i) * GROUP_SIZE + local.x];
        float weight = gMomentWeights2.y;
        if (!isInterior)
        {
            int tileX = pixel.x / TS_TILE_W;
            uint validWindow = RowValidBits(tileX - 1, pixel.y) | (RowValidBits(tileX, pixel.y) << 8) |
                               (RowValidBits(tileX + 1, pixel.y) << 16);
            float rowWeight = 0.0;
            for (int i = -RADIUS_MAX; i <= RADIUS_MAX; i++)
                rowWeight += uint(pixel.y + i) < gResourceSize.y ? MomentWeight(abs(i)) : 0.0;
            weight = WeightedRowSum(validWindow >> uint(pixel.x % TS_TILE_W)) * rowWeight;
        }
        localMean = sum / weight;
    }

    uint mask = sMask[regionTile.y * REGION_TILES_X + regionTile.x];
    float sample0 = ((mask >> uint((pixel.x % TS_TILE_W) + TS_TILE_W * (pixel.y % TS_TILE_H))) & 1u) != 0u ? 1.0 : 0.0;

    // Skipped tiles and sky: the uniform value with a full history, so that a tile turning
    // non-uniform starts from a stable, clamped history.
    float result = tileClass == TS_TILE_LIT ? 1.0 : 0.0;
    float variance = 0.0;
    bool isPersistent = false;
    float temporalMean = result;
    float samples = tileClass == TS_TILE_SKY || isSky ? 0.0 : gMaxHistoryFrameNum;
    float previousLocalMean = result; // Running mean of the local mean (the next frame's reference).
    bool isHeld = false; // See TS_HOLD_DECAY.
    float heldSample = 0.0; // The last raw sample before the drop: a settled texel's value stays its last sample.

    if (tileClass == TS_TILE_FILTERED && !isSky)
    {
        vec2 uv = _NRD_PixelUv(pixel);
        vec3 N = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_Normal, gNearestClamp), pixel, 0)).xyz;
        vec3 mv = _NRD_Sanitize(texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz, 0.0);
        vec3 Xv = _NRD_ViewPosition(uv, viewZ);
        // Frames of history a hard shadow may keep after the light's move (ShadowMotion.glsl); below
        // 1 it outputs its sample (at the end), and its history becomes the sample. A soft one's
        // (TS_MOVING_SOFT_RADII), below 1 none: the filter alone.
        float movedKeep = NRD_FP16_MAX;
        float softKeep = NRD_FP16_MAX;
        bool isFastNarrowSoft = false; // See TS_MOVING_NARROW_PENUMBRA.
        bool isNarrowAround = false; // A moving occluder's soft shadow around, its penumbrae narrow.
        bool isNarrowLit = false; // A lit sample of isNarrowAround.
#if TS_SHADOW_DATA
        if (_NRD_ShadowMotion_IsLightMoving())
        {
            float widest = -1.0; // Pixels; -1: no shadowed sample around.
            for (int j = -1; j <= 1; j++)
            {
                for (int i = -1; i <= 1; i++)
                {
                    ivec2 q = clamp(pixel + ivec2(i, j), ivec2(0), ivec2(gResourceSize) - 1);
                    float p = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), q, 0).y;
                    // NaN, negative and lit (NRD_FP16_MAX) read as no penumbra; sky holds none. A
                    // penumbra of 0 (the light below the surface's horizon) under an infinite light
                    // too: the terminator, the light's angular diameter wide on the surface (well under
                    // a pixel for a sun), turns with the light like a hard shadow, and a radius of 0
                    // would read as a shadow that never moves (venetian_blinds' sphere kept a full
                    // history of its terminator while the sun turned 2.8 penumbra radii a frame). A
                    // sphere lamp's terminator can be wide: it keeps its history as before, but where
                    // the whole lamp is below the horizon (a flat face turned away from it, exact, that
                    // turns dark or lit at once as the lamp passes its plane: a small lamp moving fast
                    // left such faces at 0.2-0.6 for frames, FLIP 1.046x the input's at 64x64, 1.006x).
                    bool isPenumbra = p > 0.0 || (p == 0.0 && gLightMotionView.w != 0.0 && !IsBelowHorizon(q));
                    if (isPenumbra && p < NRD_FP16_MAX * 0.75 && !_NRD_IsSky(texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x))
                        widest = max(widest, min(p * gProjectY, 16384.0));
                }
            }
            float perPenumbra = _NRD_ShadowMotion_PerPenumbra(Xv);
            if (widest < TS_MOVING_HARD_PENUMBRA)
                movedKeep = _NRD_ShadowMotion_KeptFrames(_NRD_ShadowMotion_Pixels(widest, perPenumbra));
            else if (perPenumbra > 0.0)
            {
                softKeep = TS_MOVING_SOFT_RADII / perPenumbra;
                isFastNarrowSoft = softKeep < 1.0 && widest < TS_MOVING_NARROW_PENUMBRA;
            }
        }
        // Shadows that moving occluders carried (TS_OCCLUDER_RADIUS, sOccluderDelta): the history is
        // taken where the 5x5 says the shadow was ('occluderShift', pixels), and kept as the estimate allows.
        vec2 occluderShift = vec2(0.0);
        {
            float occluderMotion = 0.0, occluderNum = 0.0, occluderWidest = 0.0;
            for (int j = -TS_OCCLUDER_RADIUS; j <= TS_OCCLUDER_RADIUS; j++)
            {
                for (int i = -TS_OCCLUDER_RADIUS; i <= TS_OCCLUDER_RADIUS; i++)
                {
                    int e = (local.y + TS_OCCLUDER_RADIUS + j) * OCCLUDER_REGION + local.x + TS_OCCLUDER_RADIUS + i;
                    float penumbra = sOccluderPenumbra[e];
                    if (penumbra >= 0.0)
                    {
                        vec2 d = sOccluderDelta[e];
                        occluderShift += d;
                        occluderNum += 1.0;
                        occluderWidest = max(occluderWidest, penumbra);
                        occluderMotion = max(occluderMotion, max(abs(d.x), abs(d.y)));
                    }
                }
            }
            if (occluderMotion > TS_OCCLUDER_MOVED && occluderWidest < NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA)
                movedKeep = min(movedKeep, _NRD_ShadowMotion_KeptFrames(occluderMotion));
            if (occluderMotion > TS_OCCLUDER_MOVED && occluderWidest >= NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA)
            {
                occluderShift /= occluderNum;
                float spread = 0.0;
                float nearWidest = -1.0; // The 3x3's widest penumbra.
                for (int j = -TS_OCCLUDER_RADIUS; j <= TS_OCCLUDER_RADIUS; j++)
                {
                    for (int i = -TS_OCCLUDER_RADIUS; i <= TS_OCCLUDER_RADIUS; i++)
                    {
                        int e = (local.y + TS_OCCLUDER_RADIUS + j) * OCCLUDER_REGION + local.x + TS_OCCLUDER_RADIUS + i;
                        vec2 d = abs(sOccluderDelta[e] - occluderShift);
                        spread = sOccluderPenumbra[e] >= 0.0 ? max(spread, max(d.x, d.y)) : spread;
                        if (abs(i) <= 1 && abs(j) <= 1)
                            nearWidest = max(nearWidest, sOccluderPenumbra[e]);
                    }
                }
                float uncertainty = spread + TS_OCCLUDER_MODEL * length(occluderShift);
                if (uncertainty > 0.0)
                    softKeep = min(softKeep, TS_OCCLUDER_SOFT_RADII * occluderWidest / uncertainty);
                // Penumbrae under NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA around: the 3x3's all
                // hard, the pixel is a hard shadow's (its own samples' shadows, not the wider one
                // nearby, set it).
                isNarrowAround = occluderWidest < NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA;
                if (isNarrowAround && nearWidest < NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA)
                    movedKeep = 0.0;
                isNarrowLit = isNarrowAround && sample0 != 0.0;
            }
            else
                occluderShift = vec2(0.0);
        }
#endif

        // 2. Disocclusion: the previous position of the surface point.
        vec3 previous = PreviousUv(uv, Xv, mv);
        vec2 uvPrev = previous.xy;
        float viewZPrevExpected = previous.z;
#if TS_SHADOW_DATA
        uvPrev += occluderShift * gInvResourceSize; // Where a moving occluder's shadow was.
#endif

        // The depth tolerance grows where the view grazes the surface: by the relative depth change
        // of the surface's tangent plane per pixel (a taps lies up to 1.5 pixels away), at most
        // the grazing threshold. A plane n.X = c seen along r(uv) has z = c / n.r, so one pixel
        // changes z by z * |n.dr| / |n.r|.
        vec3 Nv = N * mat3(gViewToWorld); // World -> view (transposed rotation).
        vec3 ray = Xv / viewZ;
        float slope = (abs(Nv.x) * 2.0 * gFrustum.x * gInvResourceSize.x + abs(Nv.y) * 2.0 * gFrustum.z * gInvResourceSize.y) /
                      max(abs(dot(Nv, ray)), 1e-6);
        float tolerance = min(gDisocclusionThreshold + 1.5 * slope, gDisocclusionThresholdGrazing) * viewZPrevExpected;
#if TS_SHADOW_DATA
        tolerance += slope * length(occluderShift) * viewZPrevExpected; // The surface's depth there.
#endif

        // History: Catmull-Rom over the 4x4 texels around the reprojected position where all of them
        // hold the same surface (repeated bilinear resampling would blur sharp shadows by pixels
        // under camera motion), else bilinear without the taps behind a depth discontinuity or
        // outside the image. Eight gathers: viewZ (+ previous local mean) and packed history.
        vec4 history = vec4(0.0); // History, temporal mean, samples, previous local mean.
        float footprint = 0.0;
        vec4 weighted = vec4(0.0);
        float support = 0.0, meanMin = 1.0, meanMax = 0.0;
        float resampling = 0.0; // Blur of the resampling: 0 at texel centres, 0.5 halfway on both axes.
        uint previousBits = 0u;  // Raw samples of the 4x4 footprint (bit 4 k.y + k.x), valid texels only.
        // Texels of the 4x4 footprint whose recent samples were all equal (TS_SETTLED; their last raw
        // sample, in previousBits, is then the settled value).
        uint footprintBits = 0u; // Texels of the 4x4 footprint that hold this surface.
        ivec2 nearestK = ivec2(1);
        uint youngLitBits = 0u; // Texels of the 4x4 footprint whose (at least TS_HARD_ARRIVAL_SAMPLES) samples were all lit.
        bool isOnScreen = all(greaterThan(uvPrev, vec2(-0.5))) && all(lessThan(uvPrev, vec2(1.5))); // False for NaN.
        if ((gFlags & TS_FLAG_HISTORY_VALID) != 0u && viewZPrevExpected > NRD_EPS && isOnScreen)
        {
            vec2 position = uvPrev * vec2(gResourceSize) - 0.5;
            NrdFootprint nearestTexels = _NRD_Footprint(uvPrev, vec2(gResourceSize));
            ivec2 origin = nearestTexels.origin;
            vec2 f = nearestTexels.f;
#if TS_SHADOW_DATA
            // The camera's resampling (the rules of a moving view), not the shadow's shift.
            vec2 fc = fract(position - occluderShift);
            resampling = fc.x * (1.0 - fc.x) + fc.y * (1.0 - fc.y);
#else
            resampling = f.x * (1.0 - f.x) + f.y * (1.0 - f.y);
#endif
            nearestK = ivec2(greaterThanEqual(f, vec2(0.5))) + 1;
            // Gather order: (0, 1), (1, 1), (1, 0), (0, 0) from the block's first texel; block b
            // starts at origin - 1 + 2 (b & 1, b >> 1). Gather coordinates are normalized by the
            // texture's size (gInvStateSize), which a dynamic resolution's region (gResourceSize) is
            // smaller than.
            const ivec2 offsets[4] = ivec2[4](ivec2(0, 1), ivec2(1, 1), ivec2(1, 0), ivec2(0, 0));
            // First the depths: which of the 16 texels hold this surface (bit 4 k.y + k.x), and the
            // previous local mean of the inner 2x2 (the only texels whose local mean is read).
            uint validBits = 0u;
            vec4 innerLocalMean = vec4(0.0); // Inner texel (k.x - 1) + 2 (k.y - 1).
            for (int block = 0; block < 4; block++)
            {
                ivec2 blockOrigin = origin + ivec2((block & 1) * 2 - 1, (block >> 1) * 2 - 1);
                vec2 gatherUv = (vec2(blockOrigin) + 1.0) * gInvStateSize;
                uvec4 viewZs = textureGather(usampler2D(gPrev_State, gNearestClamp), gatherUv, 0);
                for (int i = 0; i < 4; i++)
                {
                    ivec2 texel = blockOrigin + offsets[i];
                    ivec2 k = texel - origin + 1; // 0..3 in the 4x4 footprint.
                    float viewZPrev = _TS_UnpackViewZ(viewZs[i]);
                    // The outer ring lies up to 2 pixels further: a slanted surface changes depth there.
                    bool isInner = k.x >= 1 && k.x <= 2 && k.y >= 1 && k.y <= 2;
                    bool isValid = all(lessThan(uvec2(texel), gResourceSize)) && !_NRD_IsSky(viewZPrev) &&
                                   abs(viewZPrev - viewZPrevExpected) < tolerance * (isInner ? 1.0 : TS_OUTER_TOLERANCE);
                    validBits |= isValid ? 1u << uint(4 * k.y + k.x) : 0u;
                    previousBits |= isValid ? _TS_UnpackSample(viewZs[i]) << uint(4 * k.y + k.x) : 0u;
                    if (isInner)
                        innerLocalMean[(k.x - 1) + 2 * (k.y - 1)] = _TS_UnpackLocalMean(viewZs[i]);
                }
            }
            // Then the histories, in the same order.
            vec4 wx = _NRD_CatmullRomWeights(f.x), wy = _NRD_CatmullRomWeights(f.y);
            vec2 cubic = vec2(0.0); // History and temporal mean; samples and the local mean are smooth: bilinear.
            vec4 bilinear = vec4(0.0);
            for (int block = 0; block < 4; block++)
            {
                ivec2 blockOrigin = origin + ivec2((block & 1) * 2 - 1, (block >> 1) * 2 - 1);
                vec2 gatherUv = (vec2(blockOrigin) + 1.0) * gInvStateSize;
                uvec4 histories = textureGather(usampler2D(gPrev_State, gNearestClamp), gatherUv, 1);
                for (int i = 0; i < 4; i++)
                {
                    ivec2 k = blockOrigin + offsets[i] - origin + 1;
                    bool isInner = k.x >= 1 && k.x <= 2 && k.y >= 1 && k.y <= 2;
                    vec3 value = _TS_UnpackHistory(histories[i]);
                    cubic += wx[k.x] * wy[k.y] * value.xy;
                    previousBits |= value.z >= TS_SETTLED_SAMPLES && abs(value.y - 0.5) > 0.5 - TS_SETTLED ? 0x10000u << uint(4 * k.y + k.x) : 0u;
                    youngLitBits |= value.z >= TS_HARD_ARRIVAL_SAMPLES && value.y > 1.0 - TS_SETTLED ? 1u << uint(4 * k.y + k.x) : 0u;
                    if (isInner && (validBits & (1u << uint(4 * k.y + k.x))) != 0u)
                    {
                        vec4 texelValue = vec4(value, innerLocalMean[(k.x - 1) + 2 * (k.y - 1)]);
                        float w = (k.x == 1 ? 1.0 - f.x : f.x) * (k.y == 1 ? 1.0 - f.y : f.y);
                        bilinear += w * texelValue;
                        footprint += w;
                        // Likelihood of this frame's sample under the texel's temporal mean.
                        float likelihood = sample0 != 0.0 ? value.y : 1.0 - value.y;
                        weighted += (w * likelihood) * texelValue;
                        support += w * likelihood;
                        if (w > 0.01)
                        {
                            meanMin = min(meanMin, value.y);
                            meanMax = max(meanMax, value.y);
                        }
                    }
                }
            }
            footprintBits = validBits;
            bool isCubicValid = validBits == 0xFFFFu;
            history = bilinear;
            if (meanMin < TS_HARD_EDGE && meanMax > 1.0 - TS_HARD_EDGE && support > 1e-4)
            {
                // A hard edge crosses the footprint: interpolating would leak one side into the
                // other. Each texel is weighted by how well it explains this frame's sample (a
                // steep penumbra is left to the interpolation: there it would follow the noise).
                history = weighted * (footprint / support);
            }
            else if (isCubicValid) // Then the bilinear footprint is complete: 'footprint' is 1.
                history.xy = clamp(cubic, 0.0, 1.0);
        }
        // A shadowed sample that the history calls unlikely, next to several shadowed pixels: a soft
        // shadow arrived; the history restarts (and the filter takes over). Under sub-pixel motion,
        // nearly impossible next to another shadowed pixel: output as it is below. Only this direction:
        // shown wrongly, a 0 on a lit surface costs about 1 / 100 of what a 1 costs in an umbra, and
        // a penumbra arriving on a lit surface is the common false alarm.
        // Pixels outside the image count as the centre's value (a lit pixel on the border can agree
        // with its window); the 3x3 mean counts the pixels inside only.
        uint nearInImage;
        uint near = NearWindow(local, groupOrigin, isInterior, nearInImage);
        near = (near & nearInImage) | (sample0 != 0.0 ? ~nearInImage & NEAR_5X5 : 0u);
        bool isMoving = resampling > TS_MOTION_RESAMPLING;
        // (For a shadowed sample, pixels outside the image count as shadowed neighbours: on the
        // border a shadow arriving restarts the history as readily as inside.)
        int shadowedNeighbors = 8 - bitCount(near & NEAR_3X3);
        // Next to narrow penumbrae that a moving occluder carried, a pixel whose 3x3 samples all
        // agree with its own lies outside them: its sample is exact (a hard shadow's rule).
        if (isNarrowAround && ((near ^ (sample0 != 0.0 ? NEAR_5X5 : 0u)) & NEAR_3X3) == 0u)
            movedKeep = 0.0;
        bool isUnlikely = sample0 == 0.0 && support < TS_CONTRADICTION_WIDE * footprint;
        bool isContradicted =
            isUnlikely && isMoving && support < TS_CONTRADICTION * footprint && shadowedNeighbors >= 1;
        bool isRestarted = isUnlikely && !isContradicted && shadowedNeighbors >= TS_CONTRADICTION_WIDE_NEIGHBORS;
        float structure = -1.0; // ChangesRelativeToNoise, computed where a rule needs it.
        bool isPartialContradicted = footprint >= 0.01 && footprint < TS_PARTIAL_FOOTPRINT && abs(history.y / footprint - sample0) > TS_PARTIAL_CONTRADICTION;
#if TS_SHADOW_DATA
        if (isPartialContradicted)
        {
            uvec2 hard = ShadowedPenumbrae3x3(near, pixel, -1.0, TS_HARD_ARRIVAL_PENUMBRA);
            isPartialContradicted = hard.x > 0u && hard.y == 0u;
        }
#else
        isPartialContradicted = false;
#endif
        bool isDisoccluded = footprint < 0.01 || isRestarted || isPartialContradicted;
        // TS_HOLD_DECAY. A held history is lit where the samples are dark: the hold goes on whatever
        // the restart tests say (the rules below see the kept history; the end replaces their result).
        vec4 reprojected = footprint >= 0.01 ? history / footprint : vec4(0.0);
        isHeld = footprint >= 0.01 && !isMoving && sample0 == 0.0 && (near & NEAR_3X3) == 0u &&
                 reprojected.w - localMean > TS_GLOBAL_CHANGE && reprojected.z - TS_HOLD_DECAY >= TS_HOLD_MIN_SAMPLES;
        history = isDisoccluded && !isHeld ? vec4(sample0, 0.0, 0.0, localMean) : reprojected;

        // History clamped to the neighbourhood (moving shadows have no motion vectors), where the
        // neighbourhood changed: its mean against its running mean at the same surface point, in
        // standard errors. A still neighbourhood keeps its history unclamped: next to a sharp
        // shadow edge mean +- 0.5 sigma excludes the pixel's own value (0 or 1).
        float localVariance = max(localMean - localMean * localMean, 0.0);
        float localMeanError = gLocalMeanNoise * sqrt(max(localVariance, history.w - history.w * history.w)) + 2.0 / 255.0;
        float change = abs(localMean - history.w) / localMeanError;
        float clampAmount = clamp((change - TS_CHANGE_THRESHOLD) * 0.5, 0.0, 1.0);
        float halfWidth = mix(1.0, gHistoryClampSigma * sqrt(localVariance), clampAmount);
        // The box also reaches the mean of the 3x3 bits around the pixel: inside a shadow (or light)
        // that is uniform around the pixel, the wide neighbourhood's mean is biased.
        float nearMean = float(bitCount(near & nearInImage & NEAR_3X3)) / float(bitCount(nearInImage & NEAR_3X3));
        float boxMin = min(localMean - halfWidth, nearMean), boxMax = max(localMean + halfWidth, nearMean);
        float clamped = clamp(history.x, boxMin, boxMax);
        // The running mean follows faster after a large change (a light switched, the signal back).
        previousLocalMean = mix(history.w, localMean, mix(TS_LOCAL_MEAN_ALPHA, 0.5, clampAmount));

        // History outside the clamp box (a moving shadow) counts as fewer samples: the distance in
        // standard errors of the local mean, so that noise alone rarely shortens the history.
        float outside = abs(history.x - clamped) / max(gLocalMeanNoise * sqrt(localVariance), 0.002);
        float previousSamples = history.z * exp(-TS_HISTORY_REJECTION * outside * outside);
        // Where a uniform neighbourhood changed at once (a light switched on), the clamped history is
        // the new neighbourhood's mean: worth a few samples, where restarting from one would take
        // many frames to settle in the penumbrae. Elsewhere (a moving shadow) it would trail.
        bool isJump = abs(localMean - history.w) > TS_GLOBAL_CHANGE; // Also for the exact samples (TS_HARD_FRESH_SAMPLES).
        bool isSwitched = isJump && abs(history.w - 0.5) > 0.5 - TS_UNIFORM_BEFORE;
        // A light switched on over a dark neighbourhood (its local mean up by more than
        // TS_SWITCHED_ON at once; a shadow leaving a dark area raises it gradually): the history and
        // the temporal mean hold the dark frames, and the box clamp would start every pixel at the new
        // 17x17 mean (lit pixels next to an edge greyed, thin shadows lit). They start from the mean
        // of the 3x3 bits instead, and the variance comes from the bits alone: the temporal one of
        // such a clamped mean would blur lit pixels next to the new shadows for frames (FLIP of
        // toggling_light at 128x128 0.0099 -> 0.0074 against the input's 0.0090).
        bool isSwitchedOn = isSwitched && localMean - history.w > TS_SWITCHED_ON;
        if (isSwitched)
        {
            previousSamples = max(previousSamples, min(history.z, TS_CLAMPED_SAMPLES));
            previousLocalMean = localMean; // The change is over at once: no trailing clamp.
            if (isSwitchedOn)
                clamped = nearMean;
        }

        if (movedKeep >= 1.0)
            previousSamples = min(previousSamples, min(movedKeep, softKeep));

        // 3. Reprojection: running moments of the raw samples (their mean clamped like the history
        // where the neighbourhood changed), variance of a 0/1 sample from the mean.
        float previousMean = isSwitchedOn ? nearMean : (clampAmount > 0.0 ? clamp(history.y, boxMin, boxMax) : history.y);
        // Under a frame of history (a hard shadow that moved: output as sampled, at the end) the
        // history and the temporal mean become the sample, worth at most TS_MOVED_HARD_SAMPLES: a
        // shadow that moved on leaves no stale history behind for the frames in which its occluder is
        // no longer found around the pixel, the pixel's next samples still read as settled
        // (TS_HARD_ARRIVAL_SAMPLES: a one-pixel shadow moving on over them; restarting the length
        // instead took mesh_thin's relMSE ratio at 64x64 from 1.000 to 0.961), and a shadow that lay
        // there for one frame fades within a few (a thin bar's tip: kept at full length, its pixel
        // read 0.05 on the next frame, lit, truth 1).
        if (movedKeep < 1.0)
        {
            previousMean = sample0;
            clamped = sample0;
            previousSamples = min(previousSamples, TS_MOVED_HARD_SAMPLES);
        }
        samples = min(previousSamples + 1.0, mix(gMaxHistoryFrameNum, min(gMaxHistoryFrameNum, TS_CHANGING_HISTORY), clampAmount));
        temporalMean = previousMean + StepToward(sample0 - previousMean, 1.0 / samples);
        // The filter is handed the variance of the temporal estimate (of the mean of n samples), not
        // of one sample: a settled history needs little spatial filtering, and thin shadows survive.
        variance = samples > 1.0 ? temporalMean * (1.0 - temporalMean) / (samples - 1.0) : 0.0;

        // Variance boost while few samples are known: a stronger spatial filter. On a short history
        // the temporal variance means little, and the spatial one of the 3x3 bits is taken (the
        // 17x17 one is large next to a sharp edge, which would blur the edge). Without motion, 2 or
        // more samples bound it by the posterior variance of their mean (uniform prior: Beta(k + 1,
        // n - k + 1) for k lit of n): a thin shadow revealed a few frames ago, sampled the same
        // every frame, keeps its shape while a noisy penumbra around it is still filtered. From
        // TS_SPATIAL_BOOST_SAMPLES on, no more than one sample's temporal variance: a hard edge
        // that stays put (variance 0) keeps its shape.
        if (isSwitchedOn)
            variance = 0.0; // The spatial variance below only.
        if (samples < 16.0)
        {
            float spatial = nearMean * (1.0 - nearMean);
            if (samples >= (isMoving ? TS_SPATIAL_BOOST_SAMPLES_MOTION : TS_SPATIAL_BOOST_SAMPLES))
            {
                spatial = min(spatial, temporalMean * (1.0 - temporalMean));
            }
            else if (samples >= 2.0 && !isMoving)
            {
                float lit = temporalMean * samples;
                float posterior =
                    (lit + 1.0) * (samples - lit + 1.0) / ((samples + 2.0) * (samples + 2.0) * (samples + 3.0));
                spatial = min(spatial, posterior);
            }
            variance = max(variance, spatial) * max(16.0 - samples, 1.0) * (isMoving ? 1.0 : TS_BOOST_SCALE);
        }

        // Blend toward the current sample by history length, and by how much the resampling blurred
        // the history: repeated every frame of sub-pixel motion, it would wash out sharp shadows.
        // (At least 1 / n: a plain running mean until the floor of 0.05 is reached at n = 20.)
        float alpha = max(max(mix(0.05, 1.0, sqrt(max(8.0 - samples, 0.0) / 8.0)), 1.0 / max(samples, 1.0)),
                          TS_RESAMPLING_ALPHA * resampling);
        // Under motion a pixel whose 5x5 bits all agree takes its sample: inside a sharp shadow (or
        // light) the sample is exact, and the resampled history is not.
        uint agree = near ^ (sample0 != 0.0 ? NEAR_5X5 : 0u);
        // Also where the history contradicts such a uniform 5x5 window (a surface revealed next to
        // another one at the same depth, e.g. the two faces of a corner): it is someone else's.
        if (agree == 0u && (isMoving || abs(history.x - sample0) > TS_NEAR_CONTRADICTION))
        {
            alpha = 1.0;
            samples = min(samples, 1.0);
        }
        result = clamped + StepToward(sample0 - clamped, alpha);
        if (isSwitchedOn && sample0 != 0.0 && nearMean < TS_SWITCHED_ON_LIT_NEAR) // See the constant.
            result = temporalMean;

        // Temporal determinism (TS_DETERMINISTIC): this frame's bits against the previous frame's at
        // the same offsets from the nearest history texel, where both are this surface.
        float flips = 0.0, pairs = 0.0, lit = 0.0;
        float nearFlips = 0.0, nearPairs = 0.0, nearLit = 0.0;
        bool isCentreUnchanged = false;
        for (int t = 0; t < 16 && footprintBits != 0u; t++)
        {
            ivec2 d = ivec2(t & 3, t >> 2) - nearestK;
            uint nearBit = uint(d.x + 2 + 5 * (d.y + 2));
            if ((footprintBits & (1u << uint(t))) == 0u || ((nearInImage >> nearBit) & 1u) == 0u)
                continue;
            uint current = (near >> nearBit) & 1u, previous = (previousBits >> uint(t)) & 1u;
            flips += float(current ^ previous);
            pairs += 1.0;
            lit += float(current + previous);
            if (d == ivec2(0))
                isCentreUnchanged = current == previous;
            if (abs(d.x) <= 1 && abs(d.y) <= 1) // The 3x3 around the pixel (isExactShadow).
            {
                nearFlips += float(current ^ previous);
                nearPairs += 1.0;
                nearLit += float(current);
            }
        }
        // Settled texels (TS_SETTLED) whose value this frame's bit at the same offset contradicts: this
        // frame's 5x5 bits moved into the footprint's layout (the nearest texel at the centre).
        uint currentBits = 0u, currentInImage = 0u;
        for (int row = 0; row < 4; row++)
        {
            uint shift = uint(5 * (row - nearestK.y + 2) + 2 - nearestK.x);
            currentBits |= ((near >> shift) & 0xFu) << uint(4 * row);
            currentInImage |= ((nearInImage >> shift) & 0xFu) << uint(4 * row);
        }
        int contradictions = bitCount((currentBits ^ previousBits) & (previousBits >> 16) & footprintBits & currentInImage);
        float litFraction = lit / max(2.0 * pairs, 1.0);
        float expectedFlips = pairs * 2.0 * litFraction * (1.0 - litFraction);
        // Only where the history is in doubt: under motion, where the resampled history is on the other
        // side of 0.5 (elsewhere its antialiased edges are better than the sample); in a still view,
        // where the neighbourhood changed. A still sharp shadow keeps accumulating.
        bool isDeterministic = !isDisoccluded && ((isMoving && abs(history.x - sample0) > 0.5) || (!isMoving && clampAmount > 0.0)) &&
                               isCentreUnchanged &&
                               expectedFlips >= TS_DETERMINISTIC_EVIDENCE && flips <= TS_DETERMINISTIC * expectedFlips;
        // A thin shadow (1 to TS_THIN_SHADOW_NEIGHBORS shadowed neighbours, one lit) whose 3x3 bits are
        // this frame what they were the last, with at most one change in the whole 4x4 footprint (at
        // least TS_EXACT_PAIRS of the 3x3 on this surface), is exact in a still view: penumbra noise
        // repeats such a pattern rarely, a sharp or thin shadow always. While the history is short
        // (TS_SHARP_SAMPLES: a light switched on, a restart) it is output as sampled whatever its shape
        // (a thin shadow that bends has no line through the centre, and its 9x9 window looks like
        // noise, so isSharpShadow misses it). The history goes on unchanged: resetting its temporal
        // mean to the sample cost the still scenes up to 8% while they warm up. Without the shadowed
        // neighbour and the 4x4 test, bright penumbrae (a 0 in 8 lit pixels twice) passed often
        // enough at 256x256 to take issue 4's instability of the disocclusion scene above its bar.
        bool isExactShadow = !isDisoccluded && !isMoving && sample0 == 0.0 && nearPairs >= TS_EXACT_PAIRS && nearFlips == 0.0 &&
                             flips <= 1.0 && nearLit >= 1.0 && shadowedNeighbors >= 1 && shadowedNeighbors <= TS_THIN_SHADOW_NEIGHBORS &&
                             samples < TS_SHARP_SAMPLES;
        // TS_EXACT_MOVING_FLIPS: under motion, the same test on an edge pixel of either value (a pixel with a
        // neighbour of each value): its 3x3 samples are this frame what they were the last at the same
        // offsets from the nearest history texel (one change allowed where the 5x5 window has no isolated
        // pixel, see IsolatedPixels), with at most TS_EXACT_MOVING_FLIPS changes in the whole 4x4
        // footprint. Camera motion moves a hard shadow's edge over the pixels; the resampled history
        // greys the pixels on both sides of it (and small shadows, a few pixels across, that the 9x9
        // test takes for noise), where the 1-spp sample is exact.
        bool isExactMoving = isMoving && !isDisoccluded && isCentreUnchanged && nearPairs >= TS_EXACT_PAIRS &&
                             (nearFlips == 0.0 || (nearFlips <= 1.0 && IsolatedPixels(near, nearInImage) == 0u)) &&
                             flips <= TS_EXACT_MOVING_FLIPS && shadowedNeighbors >= 1 &&
                             (sample0 == 0.0 ? nearLit >= 1.0 : bitCount(near & NEAR_3X3) >= 2);
        // A shadow that moved without motion vectors over a still surface (a turning sun, an object
        // passing over a still floor, the stripes of a blind): the 17x17 local mean barely changes
        // (the clamp does not start), but several texels whose samples were equal on each of their
        // last TS_SETTLED_SAMPLES frames or more are contradicted at once (the shadow's leading or
        // trailing edge). A pixel whose history is on the other side of 0.5 from its sample restarts
        // from it. A lit sample needs more evidence: in a settled shadow an isolated lit sample is
        // more often a penumbra's noise, and a false light in an umbra costs a hundred times more in
        // relMSE (with the shadowed sample's evidence alone, grazing_floor, a still scene, went from
        // 8.63 to 7.45 at 128x128). Under motion the footprint's texels are not this frame's pixels
        // at the same offsets: the rule is for still pixels only.
        int litNeighbors = bitCount(near & NEAR_3X3) - 1;
        bool isLitEvidence = contradictions >= TS_MOVED_CONTRADICTIONS_LIT &&
                             (litNeighbors >= TS_MOVED_LIT_NEIGHBORS || (litNeighbors >= 2 && HasLine(near)));
        // TS_STRIPE_*: a thin line of light moving over texels that it keeps from settling.
        bool isMovingStripe = history.y < TS_STRIPE_MEAN && history.z >= TS_STRIPE_SAMPLES && flips >= TS_STRIPE_FLIPS &&
                              bitCount((previousBits >> 16) & footprintBits) <= TS_STRIPE_SETTLED && HasThinLine(near);
        isLitEvidence = isLitEvidence || isMovingStripe;
        // TS_LIT_AREA_PAIRS: the 3x3 lit on this frame (outside the image counts as lit) and the last.
        uint aroundNearest = 0u; // The nearest texel's 8 neighbours in the footprint, on this surface.
        for (int row = -1; row <= 1; row++)
            aroundNearest |= 0x7u << uint(4 * (nearestK.y + row) + nearestK.x - 1);
        aroundNearest &= footprintBits & ~(1u << uint(4 * nearestK.y + nearestK.x));
        bool isLitArea = litNeighbors == 8 && isCentreUnchanged && bitCount(aroundNearest) >= TS_LIT_AREA_PAIRS &&
                         (aroundNearest & ~previousBits) == 0u;
        isLitEvidence = isLitEvidence || isLitArea;
        if (!isDisoccluded && !isMoving && !isSwitched && abs(history.x - sample0) > 0.5 &&
            (sample0 == 0.0 ? contradictions >= TS_MOVED_CONTRADICTIONS : isLitEvidence))
        {
            // The history restarts from the sample, filtered with the spatial variance of its 3x3
            // bits, not boosted as a first sample's would be (a shadowed sample in sharp structure is
            // output as it is, below): several settled texels contradicted at once are evidence of a
            // moved shadow, not of noise, and the boosted filter washed out the thin shadows and
            // lines of light that moved (mesh_thin, venetian_blinds).
            result = sample0;
            temporalMean = sample0;
            samples = 1.0;
            // A moving stripe's restart keeps no variance: the filter would spread a line of light one
            // pixel wide over its dark neighbours (Tests/TiledShadowTests.cpp: 0.56 on the lines).
            bool isStripeOnly = isMovingStripe && contradictions < TS_MOVED_CONTRADICTIONS_LIT;
            variance = isStripeOnly ? 0.0 : nearMean * (1.0 - nearMean);
        }
        // TS_PERSISTENT_NEIGHBORS: the pixel's own samples say the shadow arrived, where the settled
        // texels of its footprint are too few to tell (a thin shadow, the leading edge of a stripe).
#if TS_SHADOW_DATA
        // NaN reads as not hard; lit samples carry NRD_FP16_MAX. A penumbra of 0 is a light sample below
        // the surface's horizon (SIGMA_FrontEnd_PackShadow's distance 0: a surface turning away from a
        // moving light): against a settled lit history it is as good evidence as a hard one, but it is
        // exact only where the whole light is below the horizon (isBelowHorizon, from the light the
        // application gives; a sphere lamp straddles the horizon of a face turned side-on to it: the
        // truth is the part above). The dark side of a pole under a hard sun is: left to the filter
        // under a fast orbit, it took light from the lit side (0.07 for truth 0).
        float penumbraPixels = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), pixel, 0).y * gProjectY;
        bool isHardSample = sample0 == 0.0 && penumbraPixels < TS_HARD_ARRIVAL_PENUMBRA;
        bool isBelowHorizon = isHardSample && penumbraPixels == 0.0 && IsLightBelowHorizon(Xv, Nv);
        bool isExactSample = isHardSample && (penumbraPixels > 0.0 || isBelowHorizon);
        bool isExactMovingSample = isExactSample && penumbraPixels < TS_MOVING_EXACT_PENUMBRA;
#else
        const bool isHardSample = false;
        const bool isBelowHorizon = false;
        const bool isExactSample = false;
        const bool isExactMovingSample = false;
#endif
        isPersistent = !isDisoccluded && !isMoving && !isSwitched && sample0 == 0.0 && isCentreUnchanged && history.x > 0.5 &&
                       history.z >= TS_SETTLED_SAMPLES && (shadowedNeighbors >= TS_PERSISTENT_NEIGHBORS || isHardSample) &&
                       history.y >= 1.0 - 1.25 / max(history.z, 1.0) - TS_SETTLED;
        if (isPersistent)
        {
            result = sample0;
            temporalMean = sample0;
            samples = 2.0;
        }
        // TS_HARD_FRESH_SAMPLES: an exact shadowed sample on a history of fewer than 2 samples (a
        // disocclusion, a restart on this frame or the last, a history that the clamp box rejected: the
        // length after the rejection counts; a sphere flying in front of the camera left the exact
        // shadows it uncovered to the boosted filter, 0.38 for truth 0) in a still view is output as
        // sampled (the variance is set nowhere else from here on but to the same code, below). Likewise
        // next to hard shadows that a moving light carried (TS_MOVING_LIT_NEIGHBORS), and where the 17x17
        // local mean jumped by more than TS_GLOBAL_CHANGE from its running mean (a light switched on or
        // off: the history is no evidence; isSwitched needs a uniform neighbourhood before the jump,
        // which the far floor under the sky's edge never has, the sky counting as lit: toggling_light at
        // 160x160 output 0.69 there for truth 0 on every switch frame, a relMSE ratio of 2.25, under half
        // its oracle's 5.09). Under camera motion, see TS_MOVING_EXACT_PENUMBRA.
        // A face that a moving light left below its horizon is exact at once, whatever its history (a
        // box's side as a small lamp passes its plane: 0.24 for truth 0 on the next frame).
        bool isFresh = previousSamples < TS_HARD_FRESH_SAMPLES || movedKeep < NRD_FP16_MAX || isJump;
        if (isMoving ? isExactMovingSample : isExactSample && (isFresh || (isBelowHorizon && _NRD_ShadowMotion_IsLightMoving())))
        {
            variance = TS_OUTPUT_SAMPLE - sample0;
            if (!isMoving && isJump) // See TS_EXACT_EDGE_PENUMBRA.
            {
                result = sample0;
                temporalMean = sample0;
            }
        }
        if (isDeterministic)
        {
            result = sample0;
            temporalMean = sample0;
        }

        // Under sub-pixel motion a shadowed sample is output as it is, unfiltered, unless it looks
        // like penumbra noise: its 3x3 bits, or the changes across its 9x9 window (the history keeps
        // 'result'). Outside a penumbra the sample is exact, while a history resampled every frame
        // cannot hold a sharp or thin shadow still; there a light leak into the umbra would be the
        // largest error in relative terms.
        // The same holds where the history is short (a disocclusion, a restart, a shadow that just
        // arrived): it cannot yet tell a penumbra from a sharp shadow, and the boosted filter would
        // spread the light around into a thin umbra (the common case at low resolutions, where
        // penumbrae are under a pixel wide and a 1-spp shadowed sample is exact).
        // Also, in a still view, where the history calls the shadowed sample nearly impossible
        // (TS_CONTRADICTION): a thin shadow moving without motion vectors over a still surface.
        // In a still view a one-pixel line of shadow (TS_THIN_SHADOW_NEIGHBORS) counts as sharp too:
        // its outline is as long as it is, so the 9x9 window changes value about as often as noise of
        // its mean would (a straight line about 0.64 times, a diagonal one more), and the filter
        // would wash it out (the legs' shadows of mesh_thin, the slats of venetian_blinds).
        // A dark pixel whose history is still short (TS_SHARP_SAMPLES) counts too: from
        // TS_SPATIAL_BOOST_SAMPLES on, the variance boost still spreads the light around it into it
        // (a lamp switched on again after a few frames).
        // TS_WIDE_PENUMBRA: the rules below that output a sample as it is under motion are for exact
        // samples. At 960x540 the sun's penumbrae on mesh_engine's machine are 1-4 pixels wide: the
        // shadowed samples there with a penumbra radius of 2-4 pixels, output as sampled (isSharpShadow),
        // held 0.00036 of its output's relMSE of 0.00275, and the lit ones beside them (isTurned,
        // isSettledMoving) 0.00018. Only under motion: in a still view a disoccluded wide penumbra's
        // dark samples are best output while the history is short (disocclusion at 64x64 2.94 -> 2.65
        // with the rule in still views too).
        // With the penumbrae known (TS_SHADOW_DATA), under motion the 9x9 window's changes are not
        // asked: outside wide penumbrae the sample is exact, and the outline of a thin shadow moving
        // fast across the view changes the window as often as noise would (a pole's shadow one pixel
        // wide under a camera orbiting 5 degrees a frame at 64x64 was left to the filter: 0.57-0.76
        // for truth 0, a relMSE 1.37 times the input's). Nor, where the 3x3's penumbrae are under
        // TS_NOISE_PENUMBRA, its 3x3 pattern.
#if TS_SHADOW_DATA
        bool isWidePenumbra = isMoving && ShadowedPenumbrae3x3(near, pixel, TS_WIDE_PENUMBRA, NRD_FP16_MAX).x != 0u;
        bool isNoise = IsNoisyPattern(near) &&
                       !(isMoving && ShadowedPenumbrae3x3(near, pixel, isBelowHorizon ? -1.0 : 0.0, TS_NOISE_PENUMBRA).y == 0u);
        const bool isPenumbraKnown = true;
#else
        const bool isWidePenumbra = false;
        bool isNoise = IsNoisyPattern(near);
        const bool isPenumbraKnown = false;
#endif
        bool isSharpShadow = sample0 == 0.0 && !isWidePenumbra &&
                             (isMoving || samples < TS_SPATIAL_BOOST_SAMPLES || (samples < TS_SHARP_SAMPLES && result < TS_DARK_RESULT) ||
                              (isUnlikely && support < TS_CONTRADICTION * footprint)) &&
                             !isNoise;
        if (isSharpShadow && !(isMoving && isPenumbraKnown))
        {
            if (structure < 0.0)
                structure = ChangesRelativeToNoise(local, groupOrigin, isInterior);
            // In a still view the 9x9 test alone takes a wide penumbra next to a large umbra or lit
            // area for sharp (the uniform part of the window has no changes): the 5x5 window must
            // not look like noise either, unless the pixel's own samples say it stayed dark.
            bool isDarkBefore = (history.z >= TS_SETTLED_SAMPLES && history.y < TS_SETTLED) || (samples >= 2.0 && temporalMean <= TS_SETTLED);
            isSharpShadow = (structure < TS_STRUCTURE && (isMoving || isDarkBefore || IsolatedPixels(near, nearInImage) < TS_NOISE_ISOLATED)) ||
                            (!isMoving && shadowedNeighbors <= TS_THIN_SHADOW_NEIGHBORS && HasLine(~near));
        }
        // A shadowed sample where a light was switched on restarts its history dark (the sample count
        // stays the switch's few): from the 3x3 mean, a thin shadow whose sides are a penumbra's noise
        // (toggling_light's pole) kept a grey history that the filter spread over it on the next
        // frames (0.46-0.53 for truth 0 on the second lit frame). This frame's output is left to the
        // rules above (output as sampled whatever the pattern: toggling_light at 256x256 -6.7%, not -2%).
        if (isSwitchedOn && sample0 == 0.0)
        {
            result = sample0;
            temporalMean = sample0;
        }
        // The lit counterpart of a thin shadow, in a still view: a line of light one pixel wide (2 to
        // TS_THIN_SHADOW_NEIGHBORS lit neighbours, two of them opposite each other through the pixel;
        // the gaps between the slats of a blind) whose sample was lit in the previous frame too, on a
        // short history (light that just arrived), in a 5x5 window that does not look like noise. The
        // boosted filter would darken it from the shadows on both sides.
        bool isLitLine = !isMoving && !isDisoccluded && sample0 != 0.0 && samples < TS_SPATIAL_BOOST_SAMPLES && isCentreUnchanged &&
                         litNeighbors >= 2 && litNeighbors <= TS_THIN_SHADOW_NEIGHBORS && HasLine(near) &&
                         IsolatedPixels(near, nearInImage) < TS_NOISE_ISOLATED;
        // Under motion, next to a neighbour that faces another way (a crease, a silhouette, the small
        // parts of a machine), the resampled history mixes surfaces at nearly the same depth (the
        // depth test passes them), and the filter has little of the pixel's own surface to take
        // from; the sample is exact there in all but a few pixels (the shadows that such geometry
        // casts on itself and next to itself are sharp). The history restarts from the sample,
        // which is output. (Requiring 3 such neighbours instead of one: relMSE ratio input / output
        // on mesh_engine at 64x64 0.42 instead of 0.92, camera_translation 0.83 instead of 0.92.)
        // Under motion, a sample that the blended result and the temporal mean of at least
        // TS_SETTLED_MOVING_SAMPLES samples agree with (TS_SETTLED_MOVING) is exact: the resampled
        // history is short and its variance boosted, and the filter would only take from the other
        // side of a nearby hard edge (up to 0.2 of a lit pixel next to one, light in an umbra next to a
        // lit surface). In a still view 3 equal samples are weak evidence (one pixel in 8 of binary
        // noise of mean 0.5), and a longer history needs no rule.
        bool isSettledMoving = isMoving && !isWidePenumbra && samples >= TS_SETTLED_MOVING_SAMPLES &&
                               abs(result - sample0) < TS_SETTLED_MOVING && abs(temporalMean - sample0) < TS_SETTLED_MOVING;
        // TS_MOVING_LIT_NEIGHBORS: the lit side of a hard edge that a moving light carried.
        bool isLitMovedEdge = movedKeep < NRD_FP16_MAX && sample0 != 0.0 && litNeighbors >= TS_MOVING_LIT_NEIGHBORS && !isDisoccluded;
#if TS_SHADOW_DATA
        // TS_MOVING_EXACT_LIT_NEIGHBORS: the lit side of an exact edge under camera motion, and in a
        // still view on a fresh history (TS_EXACT_EDGE_PENUMBRA).
        if ((isMoving || isFresh) && sample0 != 0.0 && litNeighbors >= TS_MOVING_EXACT_LIT_NEIGHBORS && litNeighbors < 8)
        {
            bool isExactEdge = AreShadowedNeighborsExact(
                near, pixel, isMoving ? (isDisoccluded ? TS_DISOCCLUDED_EXACT_PENUMBRA : TS_MOVING_EXACT_PENUMBRA) : TS_EXACT_EDGE_PENUMBRA, Xv, Nv);
            isLitMovedEdge = isLitMovedEdge || isExactEdge;
            if (isExactEdge && !isMoving && isJump)
            {
                result = sample0;
                temporalMean = sample0;
            }
        }
#endif
        bool isTurned = false;
        for (int i = 0; i < 9 && isMoving && !isWidePenumbra && !isTurned; i++)
        {
            ivec2 q = clamp(pixel + ivec2(i % 3 - 1, i / 3 - 1), ivec2(0), ivec2(gResourceSize) - 1);
            vec3 Nq = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_Normal, gNearestClamp), q, 0)).xyz;
            // The centre itself never is; sky has no normal.
            isTurned = dot(N, Nq) < TS_TURNED_NORMAL_COS && !_NRD_IsSky(texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x);
        }
        if (isTurned)
        {
            result = sample0;
            temporalMean = sample0;
            samples = 1.0;
        }
        // TS_HARD_ARRIVAL_PENUMBRA: a hard shadowed sample under the settled lit texel nearest to it.
        int nearest = 4 * nearestK.y + nearestK.x;
        bool isHardArrival = isHardSample && !isDisoccluded && !isMoving && ((footprintBits >> uint(nearest)) & 1u) != 0u &&
                             ((previousBits & youngLitBits) >> uint(nearest) & 1u) != 0u;
        // isLitReturn: a lit sample in a lit 3x3, in a still view, right after the pixel's one shadowed
        // sample under a settled lit history (the running mean holds exactly that one: the test of
        // isPersistent). The shadow was there for a frame (a thin leg's shadow passing over, output as
        // sampled by isHardArrival) or the sample was one dark draw of a nearly lit pixel: either way
        // the pixel is lit, and the running mean, one sample darker, was boosted by the young history
        // and output at 0.94 for truth 1 (mesh_thin at 64x64). Output as sampled; the mean goes on.
        bool isLitReturn = sample0 != 0.0 && !isDisoccluded && !isMoving && !isSwitched && litNeighbors == 8 &&
                           ((footprintBits >> uint(nearest)) & 1u) != 0u && ((previousBits >> uint(nearest)) & 1u) == 0u &&
                           history.z >= TS_SETTLED_SAMPLES && history.y >= 1.0 - 1.25 / max(history.z, 1.0) - TS_SETTLED;
        if (isLitReturn || isHardArrival || (isContradicted && !isDisoccluded) || isSharpShadow || isDeterministic || isTurned || isSettledMoving || isExactShadow || isLitLine || isPersistent || isExactMoving ||
            isLitMovedEdge || movedKeep < 1.0 || (isNarrowLit && (litNeighbors <= TS_NARROW_LIT_NEIGHBORS || (litNeighbors <= TS_THIN_SHADOW_NEIGHBORS && HasLine(near)))))
            variance = TS_OUTPUT_SAMPLE - sample0;
        else if (isFastNarrowSoft)
            variance = TS_OUTPUT_SAMPLE - PlusMean(near, nearInImage);
#if TS_SHADOW_DATA
        // See TS_EXACT_EDGE_PENUMBRA (a lit 3x3 has no edge; its variance is the temporal one).
        if (variance >= 0.0 && !isMoving && !isDisoccluded && samples < TS_TEMPORAL_ONLY_SAMPLES && bitCount(near & NEAR_3X3) < 9 &&
            AreShadowedNeighborsExact(near, pixel, TS_EXACT_EDGE_PENUMBRA, Xv, Nv))
            variance = 0.0;
#endif
#if TS_SHADOW_DATA
        // See TS_BORDER_VARIANCE (pixels outside the image left out of the exact-edge test).
        ivec2 toBorder = min(pixel, ivec2(gResourceSize) - 1 - pixel);
        if (variance > 0.0 && min(toBorder.x, toBorder.y) == 0 && bitCount(near & nearInImage & NEAR_3X3) < bitCount(nearInImage & NEAR_3X3) &&
            AreShadowedNeighborsExact(near | (~nearInImage & NEAR_5X5), pixel, TS_EXACT_EDGE_PENUMBRA, Xv, Nv))
            variance *= TS_BORDER_VARIANCE;
#endif
        if (isHeld)
        {
            result = history.x;
            temporalMean = history.y;
            samples = history.z - TS_HOLD_DECAY;
            previousLocalMean = history.w;
            variance = TS_OUTPUT_SAMPLE - sample0;
            heldSample = float((previousBits >> uint(nearest)) & 1u);
        }
    }
    else if (tileClass == TS_TILE_SHADOWED && !isSky && (gFlags & TS_FLAG_HISTORY_VALID) != 0u)
    {
        // A uniformly shadowed neighbourhood (local mean 0) over the same surface point as on the
        // last frame, in a still view: TS_HOLD_DECAY. The pixel's own state first: a steady umbra
        // (its running local mean 0) reads nothing else.
        uvec2 state = texelFetch(usampler2D(gPrev_State, gNearestClamp), pixel, 0).xy;
        vec4 kept = vec4(_TS_UnpackHistory(state.y), _TS_UnpackLocalMean(state.x));
        if (kept.w > TS_GLOBAL_CHANGE && kept.z - TS_HOLD_DECAY >= TS_HOLD_MIN_SAMPLES)
        {
            vec2 uv = _NRD_PixelUv(pixel);
            vec3 mv = _NRD_Sanitize(texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz, 0.0);
            vec3 previous = PreviousUv(uv, _NRD_ViewPosition(uv, viewZ), mv);
            isHeld = _NRD_IsOwnTexel(previous.xy, pixel, vec2(gResourceSize)) &&
                     abs(_TS_UnpackViewZ(state.x) - previous.z) < gDisocclusionThreshold * previous.z;
            if (isHeld)
            {
                result = kept.x;
                temporalMean = kept.y;
                samples = kept.z - TS_HOLD_DECAY;
                previousLocalMean = kept.w;
                variance = TS_OUTPUT_SAMPLE - sample0;
                heldSample = float(_TS_UnpackSample(state.x));
            }
        }
    }

    imageStore(gOut_Shadow, pixel, vec4(result, variance, 0.0, 0.0));
    uint moments = _TS_PackMoments(temporalMean, samples, previousLocalMean, isHeld ? heldSample : sample0);
    imageStore(gOut_Moments, pixel, uvec4(moments | (isHeld ? TS_MOMENTS_HELD : 0u), 0u, 0u, 0u));

    if (gDebugView != TS_DEBUG_NONE)
    {
        float value = 0.0;
        if (gDebugView == TS_DEBUG_LOCAL_MEAN)
            value = localMean;
        else if (gDebugView == TS_DEBUG_TEMPORAL_VARIANCE)
            value = variance;
        else if (gDebugView == TS_DEBUG_HISTORY_LENGTH)
            value = samples / TS_MAX_HISTORY;
        else if (gDebugView == TS_DEBUG_TILE_CLASS)
            value = float(tileClass) * 0.25;
        imageStore(gOut_Debug, pixel, vec4(value));
    }
}
