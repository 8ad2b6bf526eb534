// Grid convergence of one quantity from three meshes: the observed order, Richardson's
// extrapolate and Roache's grid convergence index (GCI), by the ASME procedure of Celik, Ghia,
// Roache and Freitas (2008), "Procedure for estimation and reporting of uncertainty due to
// discretization in CFD applications", J. Fluids Eng. 130, 078001; Roache (1998),
// "Verification and Validation in Computational Science and Engineering", Hermosa.
//
// f1 is the finest mesh's value, f3 the coarsest's; r21 = h2/h1 and r32 = h3/h2 > 1. With
// e21 = f2 - f1, e32 = f3 - f2 and s = sign(e32/e21), the order p solves (Celik's eqs. 3-5)
//   p = |ln|e32/e21| + q(p)| / ln r21,   q(p) = ln((r21^p - s) / (r32^p - s))
// (q = 0 for a constant ratio), the extrapolate is f_ext = (r21^p f1 - f2) / (r21^p - 1), and
//   GCI_fine = Fs |e21| / (r21^p - 1)   (absolute, in the quantity's unit; Celik divide by |f1|).
//
// How the three values behave decides the band (the rule of docs/converge.md):
//   monotone     e32/e21 > 0 and |e21| < |e32|: p as above, Fs = 1.25 (Roache's factor for three
//                meshes); p is capped at kFormalOrder, so an order above that of linear shape
//                functions, usually chance, does not shrink the band.
//   oscillatory  e32/e21 < 0: no order is defined (Celik's p with s = -1 measures the
//                oscillation, not convergence); Roache's fallback for an order that cannot be
//                trusted, Fs = 3 with p = 1, band 3 |e21| / (r21 - 1), no extrapolate.
//   divergent    e32/e21 > 0 and |e21| >= |e32| (the change does not shrink): the same fallback.
//   converged    e21 = 0: band 0 on the finest value (and p unknown).
// Only "monotone" is in the asymptotic range; the others are reported as not.
#pragma once
#include <string>

namespace talus::workflow {

inline constexpr double kFormalOrder = 2;  // linear shape functions: second order at best

enum class Convergence { Monotone, Oscillatory, Divergent, Converged };

struct GridConvergence {
  Convergence kind = Convergence::Converged;
  double order = 0;         // p (capped at kFormalOrder); NaN when not monotone
  double observed_order = 0;  // p before the cap; NaN when not monotone
  double extrapolated = 0;  // Richardson's f_ext with p; NaN when not monotone
  double safety_factor = 0; // Fs
  double band = 0;          // GCI_fine, absolute, in the quantity's unit
  double relative_band = 0; // band / |f1|; NaN when f1 = 0
  bool asymptotic = false;  // monotone only
};

// Throws talus::Error on ratios <= 1 or values that are not finite.
GridConvergence grid_convergence(double f1, double f2, double f3, double r21, double r32);

std::string convergence_name(Convergence kind);

}  // namespace talus::workflow
