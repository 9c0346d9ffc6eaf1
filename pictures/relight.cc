#include "pictures/relight.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>

#include "basis/error.h"
#include "basis/option_checker.h"
#include "basis/parallel.h"
#include "pictures/ball_geometry.h"

namespace zbrdf {
namespace {

using ball::Frame;
using ball::PixelRng;

// One frame's light as the samplers see it: the map and the floor eps of the target g.
struct Light {
  const Environment* env = nullptr;
  double eps = 0;
  double Floored(const Rgb& radiance) const { return radiance.Max() + eps; }
};

Light MakeLight(const Environment& env) {
  // The floor: 1e-3 of the mean radiance (relight.h); a black map gets a floor of 1 (its
  // estimates are 0 whatever the target).
  const double mean = env.mean_max_radiance();
  return {&env, mean > 0 ? 1e-3 * mean : 1.0};
}

// A direction proposed by the mixture q = a p_b + (1 - a) p_e, with both densities, the world
// direction and the radiance there. valid is false when the technique produced nothing or the
// direction is below the horizon (where g = 0).
struct Proposal {
  bool valid = false;
  Vec3 w, d;
  double pdf_brdf = 0, pdf_env = 0;
  Rgb radiance;
};

Proposal Propose(const Brdf& brdf, const Frame& frame, const Vec3& w_o, const Environment& env,
                 bool from_brdf, PixelRng& rng) {
  Proposal p;
  if (from_brdf) {
    const double u_lobe = rng.Uniform(), u0 = rng.Uniform(), u1 = rng.Uniform();
    const BrdfSample s = brdf.Sample(w_o, u_lobe, u0, u1);
    if (!(s.pdf > 0) || s.w_i.z <= 0) return p;
    p.w = s.w_i;
    p.pdf_brdf = s.pdf;
    p.d = frame.ToWorld(p.w);
    p.pdf_env = env.Pdf(p.d);
  } else {
    const double u0 = rng.Uniform(), u1 = rng.Uniform();
    p.d = env.Sample(u0, u1, &p.pdf_env);
    if (!(p.pdf_env > 0)) return p;
    p.w = frame.ToLocal(p.d);
    if (p.w.z <= 0) return p;
    p.pdf_brdf = brdf.Pdf(w_o, p.w);
    if (!(p.pdf_brdf > 0)) return p;
  }
  p.radiance = env.Radiance(p.d);
  p.valid = true;
  return p;
}

// The candidates' density: the mixture q = a p_b + (1 - a) p_e (relight.h).
double MixturePdf(double share, double pdf_brdf, double pdf_env) {
  return share * pdf_brdf + (1.0 - share) * pdf_env;
}

// The bridge g_b = p_b m_prev^(1-b) m_cur^b between frames, over q: an SMC move's weight.
double BridgeWeight(double b, double share, double pdf_brdf, double pdf_env, double m_prev,
                    double m_cur) {
  return pdf_brdf * std::pow(m_prev, 1.0 - b) * std::pow(m_cur, b) /
         MixturePdf(share, pdf_brdf, pdf_env);
}

// How many of a pixel's M candidates the BRDF's sampler proposes (the first ones; at least
// one), from the share a of relight.h.
int BrdfCandidates(double share, int m) {
  return std::max(1, static_cast<int>(std::lround(share * m)));
}

struct PixelContext {
  const Brdf* brdf;
  Frame frame;
  Vec3 w_o;
  const RelightOptions* options;
  int n;  // particles
  int m;  // candidates
};

void Store(const Vec3& w, double pdf_brdf, const Rgb& ratio, double weight, RelightParticle* p) {
  p->w[0] = static_cast<float>(w.x);
  p->w[1] = static_cast<float>(w.y);
  p->w[2] = static_cast<float>(w.z);
  p->pdf_brdf = static_cast<float>(pdf_brdf);
  for (int c = 0; c < 3; ++c) p->ratio[c] = static_cast<float>(ratio[c]);
  p->weight = static_cast<float>(weight);
}

Vec3 Direction(const RelightParticle& p) { return {p.w[0], p.w[1], p.w[2]}; }
Rgb Ratio(const RelightParticle& p) { return {p.ratio[0], p.ratio[1], p.ratio[2]}; }

struct Counters {
  int64_t evaluations = 0, sir_starts = 0, carried = 0, resamplings = 0, proposed = 0,
          accepted = 0;
  double ess_fraction_sum = 0;
  int64_t ess_pixels = 0;
};

// SIR for one pixel (relight.h). Writes N equally weighted particles to out (if not empty) and
// the normalizing constant's estimate to *z (0 when no candidate carries weight: no light).
Rgb Sir(const PixelContext& ctx, const Light& light, PixelRng& rng,
        std::span<RelightParticle> out, double* z, Counters& counters) {
  const int m = ctx.m, n = ctx.n;
  const int m_brdf = BrdfCandidates(ctx.options->brdf_candidate_share, m);
  const double share = static_cast<double>(m_brdf) / m;
  thread_local std::vector<Proposal> candidates;
  thread_local std::vector<double> weights;
  thread_local std::vector<int> picks;
  candidates.resize(m);
  weights.assign(m, 0.0);
  double sum = 0;
  for (int j = 0; j < m; ++j) {
    candidates[j] = Propose(*ctx.brdf, ctx.frame, ctx.w_o, *light.env, j < m_brdf, rng);
    const Proposal& c = candidates[j];
    if (!c.valid) continue;
    const double g = light.Floored(c.radiance) * c.pdf_brdf;
    const double q = MixturePdf(share, c.pdf_brdf, c.pdf_env);
    weights[j] = g / q;
    sum += weights[j];
  }
  ++counters.sir_starts;
  *z = sum / m;
  if (!(sum > 0)) return Rgb();
  for (double& w : weights) w /= sum;
  picks.resize(n);
  SystematicResample(weights, rng.Uniform(), picks);
  Rgb estimate, ratio;
  int evaluated = -1;
  for (int k = 0; k < n; ++k) {
    const Proposal& c = candidates[picks[k]];
    if (picks[k] != evaluated) {  // systematic picks are sorted: duplicates are adjacent
      ratio = ctx.brdf->Eval(c.w, ctx.w_o) * (c.w.z / c.pdf_brdf);
      evaluated = picks[k];
      ++counters.evaluations;
    }
    estimate += ratio * c.radiance / light.Floored(c.radiance);
    if (!out.empty()) {
      Store(c.w, c.pdf_brdf, ratio, 1.0 / n, &out[k]);
      out[k].light = static_cast<float>(light.Floored(c.radiance));
    }
  }
  return estimate * (*z / n);
}

// One frame of kSmcBridges for one pixel (relight.h): particles from `previous`'s target to
// `current`'s. Returns false (and leaves the estimate unset) when every particle lost its weight.
bool BridgesFrame(const PixelContext& ctx, const Light& previous, const Light& current,
                  PixelRng& rng, std::span<RelightParticle> particles, double* z, Rgb* estimate,
                  Counters& counters) {
  const int n = ctx.n, bridges = ctx.options->bridges;
  const double share = ctx.options->brdf_candidate_share;
  struct Cache {
    double m_prev, m_cur, pdf_env;
    Rgb radiance;
    bool stale;
  };
  thread_local std::vector<double> weights, increments;
  thread_local std::vector<Cache> cache, cache_copy;
  thread_local std::vector<RelightParticle> copy;
  thread_local std::vector<int> picks;
  weights.resize(n);
  increments.resize(n);
  cache.resize(n);
  for (int k = 0; k < n; ++k) {
    const Vec3 d = ctx.frame.ToWorld(Direction(particles[k]));
    Cache& c = cache[k];
    c.radiance = current.env->Radiance(d);
    c.m_prev = previous.Floored(previous.env->Radiance(d));
    c.m_cur = current.Floored(c.radiance);
    c.pdf_env = current.env->Pdf(d);
    c.stale = false;
    weights[k] = particles[k].weight;
  }
  double ess = n;
  double z_factor = 1;
  for (int step = 1; step <= bridges; ++step) {
    const double b = static_cast<double>(step) / bridges;
    for (int k = 0; k < n; ++k) {
      increments[k] = std::exp(std::log(cache[k].m_cur / cache[k].m_prev) / bridges);
    }
    const Reweighting r = ReweightParticles(weights, increments);
    if (!(r.z_factor > 0)) return false;
    z_factor *= r.z_factor;
    ess = r.ess;
    if (r.ess < ctx.options->ess_threshold * n) {
      picks.resize(n);
      SystematicResample(weights, rng.Uniform(), picks);
      copy.assign(particles.begin(), particles.end());
      cache_copy = cache;
      for (int k = 0; k < n; ++k) {
        particles[k] = copy[picks[k]];
        cache[k] = cache_copy[picks[k]];
        weights[k] = 1.0 / n;
      }
      ++counters.resamplings;
    }
    // The move: conditional (iterated) SIR (Andrieu, Lee & Vihola 2018), an independence
    // Metropolis-Hastings kernel with J - 1 proposals from q (frame t's mixture) and the current
    // particle, one of them kept in proportion to g_b / q; it leaves the bridge
    // g_b = p_b m_prev^(1-b) m_cur^b invariant.
    const int tries = ctx.options->move_candidates;
    for (int k = 0; k < n; ++k) {
      const Cache& c = cache[k];
      const double pdf_brdf = particles[k].pdf_brdf;
      const double w_current = BridgeWeight(b, share, pdf_brdf, c.pdf_env, c.m_prev, c.m_cur);
      double w_sum = w_current;
      Proposal kept;
      double kept_m_prev = 0, kept_m_cur = 0;
      for (int j = 1; j < tries; ++j) {
        const bool from_brdf = rng.Uniform() < share;
        const Proposal p = Propose(*ctx.brdf, ctx.frame, ctx.w_o, *current.env, from_brdf, rng);
        ++counters.proposed;
        if (!p.valid) continue;
        const double m_prev = previous.Floored(previous.env->Radiance(p.d));
        const double m_cur = current.Floored(p.radiance);
        const double w = BridgeWeight(b, share, p.pdf_brdf, p.pdf_env, m_prev, m_cur);
        w_sum += w;
        // Reservoir choice: the new proposal replaces the kept one with probability w / w_sum.
        if (rng.Uniform() * w_sum < w) {
          kept = p;
          kept_m_prev = m_prev;
          kept_m_cur = m_cur;
        }
      }
      if (kept.valid) {
        Store(kept.w, kept.pdf_brdf, Rgb(), particles[k].weight, &particles[k]);
        cache[k] = {kept_m_prev, kept_m_cur, kept.pdf_env, kept.radiance, true};
        ++counters.accepted;
      }
    }
  }
  *z *= z_factor;
  counters.ess_fraction_sum += ess / n;
  ++counters.ess_pixels;
  Rgb sum;
  for (int k = 0; k < n; ++k) {
    RelightParticle& p = particles[k];
    if (cache[k].stale) {
      const Vec3 w = Direction(p);
      const Rgb ratio = ctx.brdf->Eval(w, ctx.w_o) * (w.z / p.pdf_brdf);
      Store(w, p.pdf_brdf, ratio, weights[k], &p);
      ++counters.evaluations;
    }
    p.weight = static_cast<float>(weights[k]);
    sum += Ratio(p) * cache[k].radiance * (weights[k] / cache[k].m_cur);
  }
  *estimate = sum * *z;
  return true;
}

// One kSmc frame for one pixel (relight.h): a pool of M fresh candidates and the N particles of
// the previous frame, resampled into N particles by the balance-heuristic weights. With a turn,
// the carried particles are turned with the light and g_{t-1} is taken at the turned-back
// direction. Returns false (and leaves the estimate unset) when nothing in the pool carries
// weight.
bool SmcFrame(const PixelContext& ctx, const Light& previous, const Light& current,
              const std::optional<TurnAboutY>& turn, PixelRng& rng,
              std::span<RelightParticle> particles, double* z, Rgb* estimate,
              Counters& counters) {
  const int m = ctx.m, n = ctx.n;
  const int m_brdf = BrdfCandidates(ctx.options->brdf_candidate_share, m);
  const double share = static_cast<double>(m_brdf) / m;
  const double c = ctx.options->history_weight * m;
  struct Member {
    Vec3 w;
    double pdf_brdf;
    Rgb radiance;
    double light;  // Floored(radiance) on this frame
    int particle;  // the carried particle's index; -1 for a fresh candidate
  };
  thread_local std::vector<Member> pool;
  thread_local std::vector<double> weights;
  thread_local std::vector<int> picks;
  thread_local std::vector<RelightParticle> copy;
  pool.clear();
  weights.clear();
  double sum = 0, sum_sq = 0;
  auto add = [&](const Member& member, double weight) {
    if (!(weight > 0) || !std::isfinite(weight)) return;
    pool.push_back(member);
    weights.push_back(weight);
    sum += weight;
    sum_sq += weight * weight;
  };
  for (int j = 0; j < m; ++j) {
    const Proposal p = Propose(*ctx.brdf, ctx.frame, ctx.w_o, *current.env, j < m_brdf, rng);
    if (!p.valid) continue;
    const double light = current.Floored(p.radiance);
    // The carried group's target at this direction: g_{t-1} where a carried particle would have
    // come from. Turned back, the light is this frame's (Environment::TurnSince); the BRDF's
    // density is taken there.
    double g_prev = 0;
    if (turn) {
      const Vec3 w_back = ctx.frame.ToLocal(turn->Back(p.d));
      if (w_back.z > 0) g_prev = previous.Floored(p.radiance) * ctx.brdf->Pdf(ctx.w_o, w_back);
    } else {
      g_prev = previous.Floored(previous.env->Radiance(p.d)) * p.pdf_brdf;
    }
    add({p.w, p.pdf_brdf, p.radiance, light, -1},
        FreshCandidateWeight(light * p.pdf_brdf, g_prev, MixturePdf(share, p.pdf_brdf, p.pdf_env),
                             m, c));
  }
  for (int k = 0; k < n; ++k) {
    const RelightParticle& p = particles[k];
    Vec3 w = Direction(p);
    double pdf_brdf = p.pdf_brdf;
    Vec3 d = ctx.frame.ToWorld(w);
    if (turn) {
      d = Normalize(turn->Forward(d));
      w = ctx.frame.ToLocal(d);
      if (w.z <= 0) continue;
      pdf_brdf = ctx.brdf->Pdf(ctx.w_o, w);
      if (!(pdf_brdf > 0)) continue;
    }
    const Rgb radiance = current.env->Radiance(d);
    const double light = current.Floored(radiance);
    add({w, pdf_brdf, radiance, light, k},
        CarriedParticleWeight(light * pdf_brdf, static_cast<double>(p.light) * p.pdf_brdf, *z,
                              n, m, c));
  }
  if (!(sum > 0)) return false;
  counters.ess_fraction_sum += sum * sum / sum_sq / n;
  ++counters.ess_pixels;
  ++counters.resamplings;
  for (double& w : weights) w /= sum;
  picks.resize(n);
  SystematicResample(weights, rng.Uniform(), picks);
  copy.assign(particles.begin(), particles.end());
  Rgb total, ratio;
  int evaluated = -1;
  for (int k = 0; k < n; ++k) {
    const Member& member = pool[picks[k]];
    if (member.particle >= 0) ++counters.carried;
    // A carried particle's f_r cos / p_b is known unless the turn moved it.
    if (member.particle >= 0 && !turn) {
      ratio = Ratio(copy[member.particle]);
    } else if (picks[k] != evaluated) {  // systematic picks are sorted: duplicates are adjacent
      ratio = ctx.brdf->Eval(member.w, ctx.w_o) * (member.w.z / member.pdf_brdf);
      evaluated = picks[k];
      ++counters.evaluations;
    }
    total += ratio * member.radiance / member.light;
    Store(member.w, member.pdf_brdf, ratio, 1.0 / n, &particles[k]);
    particles[k].light = static_cast<float>(member.light);
  }
  *z = sum;
  *estimate = total * (sum / n);
  return true;
}

}  // namespace

const char* BallSamplerName(BallSampler sampler) {
  switch (sampler) {
    case BallSampler::kMis: return "mis";
    case BallSampler::kSir: return "sir";
    case BallSampler::kSmc: return "smc";
    case BallSampler::kSmcBridges: return "smc-bridges";
  }
  return "?";
}

BallSampler BallSamplerFromName(const std::string& name) {
  for (BallSampler sampler :
       {BallSampler::kMis, BallSampler::kSir, BallSampler::kSmc, BallSampler::kSmcBridges}) {
    if (name == BallSamplerName(sampler)) return sampler;
  }
  throw InputError("--sampler must be mis, sir, smc or smc-bridges (got '" + name + "')");
}

void RelightOptions::Validate() const {
  ball.Validate();
  OptionChecker check("RelightOptions");
  check.AtLeast("candidates", candidates, 0)
      .AtLeast("bridges", bridges, 1)
      .AtLeast("move_candidates", move_candidates, 2)
      .Require(history_weight > 0 && std::isfinite(history_weight), "history_weight",
               "must be a positive number (got " + FormatOptionValue(history_weight) + ")")
      .Require(brdf_candidate_share > 0 && brdf_candidate_share <= 1, "brdf_candidate_share",
               "must be in (0, 1]: the BRDF's sampler must propose (got " +
                   FormatOptionValue(brdf_candidate_share) + ")")
      .Require(ess_threshold >= 0 && ess_threshold <= 1, "ess_threshold",
               "must be in [0, 1] (got " + FormatOptionValue(ess_threshold) + ")")
      .Require(ball.light_direction == std::nullopt, "ball.light_direction",
               "relighting needs an environment, not a directional light")
      .ThrowIfInvalid();
}

Reweighting ReweightParticles(std::span<double> weights, std::span<const double> incremental) {
  ZBRDF_ASSERT(weights.size() == incremental.size(), "ReweightParticles: sizes differ");
  Reweighting r;
  for (size_t k = 0; k < weights.size(); ++k) r.z_factor += weights[k] * incremental[k];
  if (!(r.z_factor > 0)) return {};
  double sum_sq = 0;
  for (size_t k = 0; k < weights.size(); ++k) {
    weights[k] = weights[k] * incremental[k] / r.z_factor;
    sum_sq += weights[k] * weights[k];
  }
  r.ess = 1.0 / sum_sq;
  return r;
}

double FreshCandidateWeight(double g_t, double g_prev, double q, int m, double c) {
  return g_t * g_t / ((m * g_t + c * g_prev) * q);
}

double CarriedParticleWeight(double g_t, double g_prev, double z_prev, int n, int m, double c) {
  return c / n * g_t * z_prev / (m * g_t + c * g_prev);
}

void SystematicResample(std::span<const double> weights, double u, std::span<int> indices) {
  ZBRDF_ASSERT(!weights.empty() && u >= 0 && u < 1, "SystematicResample: bad input");
  const size_t n = indices.size();
  double cumulative = weights[0];
  size_t i = 0;
  for (size_t k = 0; k < n; ++k) {
    const double target = (static_cast<double>(k) + u) / static_cast<double>(n);
    while (target >= cumulative && i + 1 < weights.size()) cumulative += weights[++i];
    indices[k] = static_cast<int>(i);
  }
}

BallSequence::BallSequence(const Brdf& brdf, RelightOptions options)
    : brdf_(brdf), options_(std::move(options)) {
  options_.Validate();
  if (options_.candidates == 0) options_.candidates = 4 * options_.ball.spp;
}

BallImage BallSequence::Render(const Environment& env, RelightStats* stats) {
  const int frame = frame_++;
  const BallOptions& ball_options = options_.ball;
  const int size = ball_options.size;
  if (options_.sampler == BallSampler::kMis) {
    BallOptions mis = ball_options;
    mis.sampling = BallOptions::Sampling::kMis;
    mis.jitter = false;
    mis.seed = ball_options.seed + static_cast<uint64_t>(frame) * 0x9E3779B9ull;
    BallImage image = RenderBall(brdf_, &env, mis);
    if (stats) {
      *stats = {};
      for (uint8_t c : image.coverage) stats->pixels += c;
      stats->brdf_evaluations = stats->pixels * 2 * mis.spp;
    }
    return image;
  }
  const int n = ball_options.spp;
  const bool bridges = options_.sampler == BallSampler::kSmcBridges;
  const bool smc = options_.sampler == BallSampler::kSmc || bridges;
  const size_t pixel_count = static_cast<size_t>(size) * size;
  if (smc && particles_.empty()) {
    particles_.resize(pixel_count * n);
    z_.assign(pixel_count, 0.0);
  }
  const Light current = MakeLight(env);
  const Light previous = previous_ ? MakeLight(*previous_) : Light{};
  // kSmc carries its particles with the light when this map is the previous one turned.
  std::optional<TurnAboutY> turn;
  if (previous_) {
    if (const std::optional<double> r = env.TurnSince(*previous_); r && *r != 0) turn.emplace(*r);
  }
  BallImage out;
  out.image = RgbImage(size, size);
  out.coverage.assign(pixel_count, 0);
  std::atomic<int64_t> pixels{0}, evaluations{0}, sir_starts{0}, carried{0}, resamplings{0},
      proposed{0}, accepted{0}, ess_pixels{0};
  std::atomic<double> ess_sum{0};
  ParallelFor(size, 1, [&](int64_t row_begin, int64_t row_end) {
    Counters counters;
    int64_t row_pixels = 0;
    for (int y = static_cast<int>(row_begin); y < row_end; ++y) {
      for (int x = 0; x < size; ++x) {
        const size_t i = static_cast<size_t>(y) * size + x;
        const ball::PixelView view = ball::ViewThrough(ball_options, x + 0.5, y + 0.5);
        if (!view.on_ball) {
          out.image.pixels[i] = env.Radiance(view.direction);
          continue;
        }
        out.coverage[i] = 1;
        if (view.w_o.z <= 0) continue;
        ++row_pixels;
        if (brdf_.IsDelta()) {
          const BrdfSample s = brdf_.Sample(view.w_o, 0.5, 0.5, 0.5);
          if (s.pdf > 0 && s.w_i.z > 0) {
            out.image.pixels[i] = s.delta_reflectance * env.Radiance(view.frame.ToWorld(s.w_i));
          }
          continue;
        }
        PixelRng rng(ball_options.seed, x, y, static_cast<uint64_t>(frame) + 1);
        const PixelContext ctx{&brdf_, view.frame, view.w_o, &options_, n, options_.candidates};
        std::span<RelightParticle> particles;
        if (smc) particles = std::span<RelightParticle>(particles_).subspan(i * n, n);
        Rgb estimate;
        bool done = false;
        if (smc && previous_ && z_[i] > 0) {
          done = bridges ? BridgesFrame(ctx, previous, current, rng, particles, &z_[i],
                                        &estimate, counters)
                         : SmcFrame(ctx, previous, current, turn, rng, particles, &z_[i],
                                    &estimate, counters);
        }
        if (!done) {
          double z = 0;
          estimate = Sir(ctx, current, rng, particles, &z, counters);
          if (smc) z_[i] = z;
        }
        out.image.pixels[i] = estimate;
      }
    }
    pixels += row_pixels;
    evaluations += counters.evaluations;
    sir_starts += counters.sir_starts;
    carried += counters.carried;
    resamplings += counters.resamplings;
    proposed += counters.proposed;
    accepted += counters.accepted;
    ess_pixels += counters.ess_pixels;
    double expected = ess_sum.load();
    while (!ess_sum.compare_exchange_weak(expected, expected + counters.ess_fraction_sum)) {
    }
  });
  if (smc) previous_ = std::make_unique<Environment>(env);
  if (stats) {
    *stats = {};
    stats->pixels = pixels;
    stats->brdf_evaluations = evaluations;
    stats->sir_starts = sir_starts;
    stats->carried = carried;
    stats->resamplings = resamplings;
    stats->moves_proposed = proposed;
    stats->moves_accepted = accepted;
    stats->mean_ess_fraction = ess_pixels > 0 ? ess_sum.load() / ess_pixels.load() : 0.0;
  }
  return out;
}

}  // namespace zbrdf
