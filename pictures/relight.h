// Material balls under changing light: the samplers of `zbrdf preview --sampler`, and the state
// sequential Monte Carlo carries from frame to frame (docs/preview.md, "Relighting").
//
// Each pixel of the ball estimates the radiance it reflects toward the camera,
//   I_t = integral f_r(w_i, w_o) L_t(w_i) cos(theta_i) dw_i,
// under frame t's environment L_t, with w_o the view direction through the pixel centre (no
// jitter: a pixel's particles belong to one w_o across frames). The samplers:
//
// kMis  per sample one BRDF and one environment sample, power heuristic (RenderBall).
// kSir  sampling-importance-resampling, the bidirectional importance sampling of Burke, Ghosh &
//       Heidrich 2005 in the unbiased form of Talbot, Cline & Egbert 2005. M candidates: a share
//       a from the BRDF's sampler (density p_b, Brdf::Sample) and the rest from the environment
//       (p_e), so their density is the mixture q = a p_b + (1 - a) p_e. The resampling target is
//         g(w) = (max_rgb L(w) + eps) p_b(w)   for w above the horizon, else 0,
//       the lighting times the BRDF's own sampling density (Ghosh 2007 section 3.4: the D-BRDF's
//       p(h) is close to f_r cos), so candidates cost no BRDF evaluation; eps is 1e-3 of the
//       map's mean radiance, so that g > 0 wherever p_b > 0 (see kSmc). N particles are drawn in
//       proportion to g / q (systematic resampling) and only they evaluate the BRDF:
//         I = Z (1/N) sum_k f_r cos L / g (w_k),   Z = (1/M) sum_j g / q (w_j),
//       which is unbiased for every M and N.
// kSmc  sequential Monte Carlo with the particles carried from frame to frame (after Ghosh,
//       Doucet & Heidrich 2006), weighted as in generalized resampled importance sampling (Lin
//       et al. 2022). A pixel without particles (the first frame, or one whose pool carries no
//       weight) starts with kSir. On a later frame the pool is the M fresh candidates of frame t
//       and the N particles of frame t - 1, each with an unbiased contribution weight (fresh:
//       1 / q; carried: Z_{t-1} / g_{t-1}), and the two groups share every direction by the
//       balance heuristic over the frames' targets with confidences M and C = history_weight M:
//         m_fresh(w) = g_t(w) / D(w) each,  m_carried(w) = (C / N) g_{t-1}(w) / D(w) each,
//         D = M g_t + C g_{t-1},
//       so the resampling weights are
//         fresh   g_t^2 / (D q),   carried   (C / N) g_t Z_{t-1} / D,
//       Z_t is their sum, and N particles are resampled from the pool in proportion to them
//       (systematic): I_t = Z_t (1/N) sum_k f_r cos L_t / g_t (w_k), unbiased (the partition
//       of unity and the contribution weights carry the proof from frame to frame;
//       docs/preview.md). Where the light did not change, Z_t = (M Z_fresh + C Z_{t-1}) / (M + C):
//       a running average over frames. Where it changed, a particle whose light left it loses
//       its weight and a fresh candidate where light appeared takes the whole of it; the
//       weights are bounded (carried <= Z_{t-1} / N, fresh <= g_t / (M q)), unlike chained
//       incremental weights. A carried particle needs no BRDF evaluation (f_r cos / p_b is
//       kept); a fresh candidate costs one more environment lookup (frame t - 1's map).
//       A turntable (frame t's map is frame t - 1's turned by r about +y,
//       Environment::TurnSince) carries the particles with the light instead: a particle at
//       w moves to T(w), w turned by r (a rotation: Jacobian 1, so its contribution weight
//       Z_{t-1} / g_{t-1}(w) is unchanged), and the carried group's target at a direction y is
//       g_{t-1}(T^-1(y)), in the weights above for fresh and carried members alike (so they
//       still sum to one at every y). L_{t-1}(T^-1(y)) = L_t(y), so this costs a BRDF density
//       at T^-1(y) per fresh candidate, and a density and, when picked, an evaluation per
//       carried particle, instead of the previous map's lookup. This is the shift mapping of
//       GRIS (the motion-vector reuse of ReSTIR) with the turn as the motion. A particle turned
//       below the horizon drops out.
// kSmcBridges  the seed paper's scheme, kept for comparison (it loses to SIR everywhere we
//       measured, docs/preview.md): a later frame moves the previous frame's particles from
//       g_{t-1} to g_t through K geometric bridges g_{t-1}^(1-b) g_t^b,
//       b = 1/K, 2/K, ..., 1; at each: reweight by the bridges' ratio, Z *= sum_k W_k inc_k,
//       resample (systematic) when the effective sample size 1 / sum W_k^2 falls below
//       ess_threshold N, then one independence Metropolis-Hastings move per particle (proposal
//       q of frame t) that leaves the bridge invariant. The estimate
//         I_t = Z_t sum_k W_k f_r cos L_t / g_t (w_k)
//       is unbiased: Z_t is the product of the incremental weights' means, not the path-sampling
//       (thermodynamic integration) estimate of log(Z_t / Z_{t-1}), whose exponential is biased.
//       Its error compounds over frames: Z_t's relative variance grows with every transition,
//       and the incremental weights g_t / g_{t-1} are heavy-tailed when a small source moves.
//
// Every sampler's target has the floor eps, which keeps the support of g_t the support of p_b
// on every frame, as carrying particles between frames needs.
//
// A delta material (a perfect mirror) needs no sampling: every sampler returns
// delta_reflectance L(mirror direction).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "pictures/environment.h"
#include "pictures/material_ball.h"

namespace zbrdf {

enum class BallSampler { kMis, kSir, kSmc, kSmcBridges };

// The samplers' names on the command line and in records: "mis", "sir", "smc", "smc-bridges".
const char* BallSamplerName(BallSampler sampler);
// The sampler of that name; throws InputError naming every sampler for any other.
BallSampler BallSamplerFromName(const std::string& name);

struct RelightOptions {
  // size, camera, seed; spp = MIS samples per pixel, or SIR's and SMC's particles per pixel (N).
  // sampling and jitter are ignored (MIS, no jitter).
  BallOptions ball;
  BallSampler sampler = BallSampler::kSmc;
  int candidates = 0;                   // SIR's candidates per pixel, M; 0: 4 N
  double brdf_candidate_share = 0.5;    // a: the share of candidates drawn from the BRDF, (0, 1]
  double history_weight = 1;            // SMC: C / M, the carried particles' confidence, > 0
  int bridges = 2;                      // SMC bridges: distributions per frame, K >= 1
  int move_candidates = 4;              // SMC bridges: J, proposals per move (with the particle)
  double ess_threshold = 0.5;           // SMC bridges: resample when ESS < ess_threshold N

  // Throws InvalidOptions (an InputError) naming every field out of range.
  void Validate() const;
};

struct RelightStats {
  int64_t pixels = 0;           // pixels on the ball that were estimated
  int64_t brdf_evaluations = 0;
  int64_t sir_starts = 0;       // pixels (re)started with SIR this frame
  int64_t carried = 0;          // SMC: particles resampled from the previous frame's
  int64_t resamplings = 0;      // SMC: resampling steps (summed over pixels and bridges)
  int64_t moves_proposed = 0, moves_accepted = 0;
  double mean_ess_fraction = 0;  // SMC: mean over pixels of the ESS / N of the last weights
                                 // before resampling (SMC: the pool's, which may exceed 1)
};

// A pixel's SMC particle (internal; declared here for BallSequence's storage).
struct RelightParticle {
  float w[3];      // incident direction, shading frame
  float pdf_brdf;  // p_b(w)
  float ratio[3];  // f_r cos(theta_i) / p_b, RGB
  float weight;    // normalized within the pixel
  float light;     // max_rgb L + eps at w on the frame it was last resampled on (kSmc)
};

// Renders a sequence of frames of one BRDF seen by one camera. Not thread-safe; each frame is
// rendered in parallel over rows and is deterministic for a given seed whatever the thread count.
class BallSequence {
 public:
  // Keeps a reference to brdf. Throws InputError for bad options.
  BallSequence(const Brdf& brdf, RelightOptions options);

  // The next frame under env. SMC carries its particles from the previous call's environment
  // (which the sequence keeps a cheap copy of), turned with the light when env is that map
  // turned (Environment::Rotated copies of one map; see kSmc).
  BallImage Render(const Environment& env, RelightStats* stats = nullptr);
  int frames_rendered() const { return frame_; }

 private:
  const Brdf& brdf_;
  RelightOptions options_;
  int frame_ = 0;
  std::vector<RelightParticle> particles_;  // N per pixel, row-major pixels
  std::vector<double> z_;            // per pixel; 0 = no particles
  std::unique_ptr<Environment> previous_;
};

// SMC building blocks, exposed for tests.
//
// Multiplies normalized weights by the incremental weights and renormalizes them in place.
// Returns the factor by which the normalizing constant's estimate grows (sum_k W_k inc_k) and
// the effective sample size 1 / sum_k W_k^2 after reweighting (0 when every weight is 0, in
// which case the weights are left as they were).
struct Reweighting {
  double z_factor = 0;
  double ess = 0;
};
Reweighting ReweightParticles(std::span<double> weights, std::span<const double> incremental);

// kSmc's resampling weights (see above), for targets g_t and g_{t-1} at the direction, fresh
// candidates' density q, M fresh candidates, N carried particles, confidence C of the carried
// ones and the previous frame's normalizing constant z_prev.
double FreshCandidateWeight(double g_t, double g_prev, double q, int m, double c);
double CarriedParticleWeight(double g_t, double g_prev, double z_prev, int n, int m, double c);

// Systematic resampling (Kitagawa 1996): indices[k] is the cell of (k + u) / N in the cumulative
// normalized weights, u in [0, 1). Each index i appears floor or ceil of N W_i times.
void SystematicResample(std::span<const double> weights, double u, std::span<int> indices);

}  // namespace zbrdf
