// Adaptive capture: take only what the sample needs (docs/adaptive.md has the math).
//
// Three decisions are made while the session runs, from the session's own frames, so that an
// adaptive session is one ordinary session folder (one plan, one journal, resumable):
//
//  * Order, band by band. The plan is made for the largest order the user allows, and lobes come
//    band by band (l = 0, 1, ...). When the last lobe of band l is in, the processor's z_lm(w_r)
//    give the band's energy E_l = sum_m sum_cells Omega_c z_lm(c)^2 and its noise energy
//    N_l = sum_m sum_cells Omega_c Var z_lm(c). Variances miss the capture's systematic errors;
//    when the first bands show the material isotropic, every z_lm(w_r) must be a single azimuthal
//    harmonic, and the energy outside it (R_l) measures the band's whole error, so the floor is
//    F_l = max(N_l, R_l) (else N_l). Errors the rig's rotational symmetry makes isotropic too
//    (pattern radiance errors that depend on theta) pass that test; they are measured once on a
//    Lambertian target, whose bands l >= 2 are zero (f cos theta_i is linear in cos theta_i, and
//    the zonal basis is linear in cos theta): lambda_l = E_l / sum_{l'<l} E_l' there, and
//    F_l >= lambda_l sum_{l'<l} E_l'. The band's signal is S_l = E_l - F_l. Keeping a band adds F_l
//    of squared error and removes S_l, so the capture stops at the first band (beyond min_order)
//    with S_l < noise_ratio F_l and drops that band; or once the predicted relative error
//    sqrt((F + T) / S) is below the user's target, T being the energy of the bands not taken,
//    extrapolated geometrically from the last two. session.json's plan is then rewritten to the
//    order kept (the frames of a dropped band stay on disk, outside the plan), with the bands'
//    energies under "adaptive".
//
//  * Exposures, per pattern. The bracket has two frames: the first at the metered shortest
//    exposure t0 (full white at 70% of the range: no lobe clips there), the second at
//    t0 * min(max_ratio, target_level * range / q), q the first frame's clip_quantile of the
//    signal: the longest exposure that keeps the pattern's response inside the range (the
//    shortest frame covers the few pixels above the quantile). The first frame is the metering
//    frame and also a measurement; the HDR merge uses the exposures the journal records.
//
//  * Lobes, once bands 0..max(1, min_order) show the material isotropic: the lobes of Z_l,-m and
//    the negative lobes of Z_l,m (m > 0) are not captured; the processor synthesizes their
//    functions by the rotations isotropy implies (ZonalProcessor::AddLobe). They keep their frame
//    indices (no frames are journaled for them); session.json's "adaptive" lists them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "acquisition/plan.h"
#include "acquisition/processing.h"
#include "acquisition/rig_calibration.h"
#include "acquisition/zonal.h"
#include "drivers/camera.h"

namespace zbrdf {

struct AdaptiveOptions {
  bool enabled = false;
  // Isotropy test on bands 0..min_order: sum off_harmonic / sum energy below this and the
  // material is taken as isotropic; each band's error floor is then max(noise, off_harmonic).
  double isotropy_threshold = 0.02;
  // The rig's systematic floor, measured once on a Lambertian target (whose bands >= 2 are zero;
  // see FloorProfile): lambda_l = E_l / sum_{l' < l} E_l' there. Band l's floor is then at least
  // lambda_l times the energy of the bands below it. Empty: variances (and isotropy) only.
  std::vector<double> floor_profile;
  int min_order = 1;        // bands 0..min_order are always taken
  double error_target = 0;  // relative L2 of the coefficients; 0: stop at the noise floor only
  double noise_ratio = 1;   // a band is kept while its signal energy > noise_ratio x its noise
  bool adaptive_exposures = true;  // false: the bracket of CaptureJobOptions, as for a fixed plan
  // Once bands 0..max(1, min_order) show the material isotropic, skip the lobes isotropy makes
  // redundant in later bands (those of Z_l,-m and the negative ones of Z_l,m, m > 0).
  bool skip_isotropic = true;
  double max_ratio = 16;  // second exposure at most this times the first (4 f-stops)
  double clip_quantile = 0.995;
  double target_level = 0.9;  // of the sensor's range (black to saturation) at that quantile

  // Throws InvalidOptions (an InputError) naming every field out of range and the values it
  // accepts (basis/option_checker.h).
  void Validate() const;
  nlohmann::json ToJson() const;
  static AdaptiveOptions FromJson(const nlohmann::json& j);
};

// One band's energy over the exitant zone (all channels), and the part the noise contributes.
struct AdaptiveBand {
  int l = 0;
  double energy = 0;  // sum_m sum_cells Omega_c z^2
  double noise = 0;   // sum_m sum_cells Omega_c Var z
  // The part of the energy outside each function's own azimuthal harmonic in w_r (cos m phi_r for
  // m >= 0, sin |m| phi_r for m < 0): zero for an isotropic material, so for one it measures the
  // band's error, systematic errors included, which the variances miss.
  double off_harmonic = 0;
  double floor = 0;  // the error energy used by the stopping rule (DecideAfterBand)
  double signal() const { return energy - floor; }
};

// `functions` are z_l,-l .. z_l,l on `grid`; `floor` is set to `noise`.
AdaptiveBand MeasureBandEnergy(int l, const std::vector<const GridImage*>& functions,
                               const ExitantGrid& grid);

struct AdaptiveDecision {
  bool stop = false;
  int order = 0;               // the order to keep (meaningful when stop)
  std::string reason;          // "noise floor", "error target"
  double predicted_error = 0;  // sqrt((N + T) / S) over the bands kept
};

// The floor profile (AdaptiveOptions::floor_profile) from the bands of a Lambertian target.
std::vector<double> FloorProfile(const std::vector<AdaptiveBand>& lambertian_bands);

// After band bands.back().l (bands 0..l in order; their `floor` set by the caller).
AdaptiveDecision DecideAfterBand(const std::vector<AdaptiveBand>& bands,
                                 const AdaptiveOptions& options);

// The exposure of the second frame of a pattern's bracket, from its first frame (see above).
double AdaptiveExposureUs(const Frame& first, const RigCalibration& calibration,
                          const AdaptiveOptions& options);

// The plan with the bands above `order` removed; the frame indices of what is kept do not change
// (lobes come band by band).
CapturePlan TruncatePlan(const CapturePlan& plan, int order);

// Runs the two decisions for one capture (RunCaptureJob wires it into RunCapture and the
// processor). Not thread-safe; called from the capture thread.
class AdaptiveController {
 public:
  AdaptiveController(const CapturePlan& plan, const RigCalibration& calibration,
                     const AdaptiveOptions& options, ZonalProcessor* processor);
  double ExposureUs(int lobe, int exposure, const std::vector<const Frame*>& shorter) const;
  bool StopAfterLobe(int lobe);
  bool SkipLobe(int lobe);
  // What SkipLobe would say now, without recording it (for the patterns told ahead).
  bool WouldSkipLobe(int lobe) const;
  const std::vector<std::string>& skipped_lobes() const { return skipped_; }
  // The order to keep once the capture ended (the plan's if it never stopped).
  int order() const { return order_; }
  const AdaptiveDecision& decision() const { return decision_; }
  const std::vector<AdaptiveBand>& bands() const { return bands_; }
  // {"options", "max_order", "order", "reason", "predicted_error", "bands": [{l, energy, noise}]}
  nlohmann::json Report() const;

 private:
  const CapturePlan& plan_;
  const RigCalibration& calibration_;
  AdaptiveOptions options_;
  ZonalProcessor* processor_;
  std::vector<int> band_end_;  // lobe index of each band's last lobe
  std::vector<AdaptiveBand> bands_;
  bool isotropic_ = false;
  std::vector<std::string> skipped_;
  AdaptiveDecision decision_;
  int order_;
};

}  // namespace zbrdf
