// Evaluates and samples a BRDF a reader produced at a few fixed directions, so that the fuzz
// targets also reach the tables and parameters the reader accepted.
#pragma once

#include "basis/vec3.h"
#include "brdf/brdf.h"

namespace zbrdf::fuzz {

inline void ProbeBrdf(const Brdf& brdf) {
  const Vec3 w_o = Normalize(Vec3{0.3, -0.2, 0.9});
  for (const Vec3& w_i : {Vec3{0, 0, 1}, Normalize(Vec3{-0.5, 0.1, 0.4}),
                          Normalize(Vec3{0.99, 0, 0.01}), Normalize(Vec3{-0.3, 0.2, 0.9})}) {
    (void)brdf.Eval(w_i, w_o);
    (void)brdf.Pdf(w_o, w_i);
  }
  (void)brdf.Sample(w_o, 0.25, 0.5, 0.75);
  (void)brdf.Sample(Vec3{0, 0, 1}, 0.9, 0.1, 0.3);
}

}  // namespace zbrdf::fuzz
