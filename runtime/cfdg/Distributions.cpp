// Context Free's random distributions (`rand::normal`, `randint::poisson`, …; lcjit/cfdg.h's
// __cf_distribution), drawn as cfdg 3.4 draws them: it carries a copy of libc++'s <random> of about
// 2015, whose algorithms (rejection loops and all) decide how many numbers each draw takes from the
// running random state, so a design's later replacements get the seeds they get in Context Free
// only if every distribution consumes the generator exactly as that code does. Each call builds a
// fresh distribution (no cached second normal deviate), with the arguments sanitised as Context
// Free's Rand64 does (probabilities clamped to [0, 1], positive parameters at least DBL_EPSILON,
// degrees of freedom whole and at least 1, trial counts at least 1).
#include "runtime/cfdg/Distributions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "runtime/cfdg/Expander.h"

namespace lcjit::runtime::cfdg {
namespace {

// The engine as <random> sees it: xorshift64*'s raw 64-bit output (min 1, max 2^64 - 1).
struct Generator {
  uint64_t& state;
  uint64_t operator()() {
    uint64_t out = state * 2685821657736338717ull;
    state = stepSeed(state);
    return out;
  }
};

// generate_canonical<double, 53> for that range: log2 of the range is 63 bits, so one call;
// (output - min) rounded to a double, over 2^64 (it can round up to 1).
double canonical(Generator& g) { return double(g() - 1u) / 18446744073709551616.0; }
double uniform(Generator& g, double a, double b) { return (b - a) * canonical(g) + a; }

// The polar method; the second deviate it makes is dropped with the distribution.
double normal(Generator& g, double mean, double sd) {
  double u, v, s;
  do {
    u = uniform(g, -1, 1);
    v = uniform(g, -1, 1);
    s = u * u + v * v;
  } while (s > 1 || s == 0);
  return u * std::sqrt(-2 * std::log(s) / s) * sd + mean;
}

double exponential(Generator& g, double lambda) { return -std::log(1.0 - canonical(g)) / lambda; }

// Marsaglia–Tsang-like rejection for alpha > 1, Johnk-like for alpha < 1 (libc++'s).
double gamma(Generator& g, double alpha, double beta) {
  double x;
  if (alpha == 1) {
    x = exponential(g, 1.0);
  } else if (alpha > 1) {
    const double b = alpha - 1, c = 3 * alpha - 0.75;
    while (true) {
      const double u = uniform(g, 0, 1), v = uniform(g, 0, 1), w = u * (1 - u);
      if (w != 0) {
        const double y = std::sqrt(c / w) * (u - 0.5);
        x = b + y;
        if (x >= 0) {
          const double z = 64 * w * w * w * v * v;
          if (z <= 1 - 2 * y * y / x) break;
          if (std::log(z) <= 2 * (b * std::log(x / b) - y)) break;
        }
      }
    }
  } else {
    while (true) {
      const double u = uniform(g, 0, 1), es = exponential(g, 1.0);
      if (u <= 1 - alpha) {
        x = std::pow(u, 1 / alpha);
        if (x <= es) break;
      } else {
        const double e = -std::log((1 - u) / alpha);
        x = std::pow(1 - alpha + alpha * e, 1 / alpha);
        if (x <= e + es) break;
      }
    }
  }
  return x * beta;
}

bool bernoulli(Generator& g, double p) { return uniform(g, 0, 1) < p; }

int64_t binomial(Generator& g, int64_t t, double p) {
  int64_t r0 = 0;
  double pr = 0, odds = 0;
  if (0 < p && p < 1) {
    r0 = int64_t((t + 1) * p);
    pr = std::exp(std::lgamma(t + 1.) - std::lgamma(r0 + 1.) - std::lgamma(t - r0 + 1.) + r0 * std::log(p) +
                  (t - r0) * std::log(1 - p));
    odds = p / (1 - p);
  }
  if (t == 0 || p == 0) return 0;
  if (p == 1) return t;
  double u = uniform(g, 0, 1) - pr;
  if (u < 0) return r0;
  double pu = pr, pd = pr;
  int64_t ru = r0, rd = r0;
  while (true) {
    if (rd >= 1) {
      pd *= rd / (odds * (t - rd + 1));
      u -= pd;
      if (u < 0) return rd - 1;
    }
    --rd;
    ++ru;
    if (ru <= t) {
      pu *= (t - ru + 1) * odds / ru;
      u -= pu;
      if (u < 0) return ru;
    }
  }
}

// Below a mean of 10 by multiplying uniforms; above, Ahrens and Dieter's method as libc++ has it.
int64_t poisson(Generator& g, double mean) {
  int64_t x = 0;
  if (mean < 10) {
    const double l = std::exp(-mean);
    for (double p = uniform(g, 0, 1); p > l; ++x) p *= uniform(g, 0, 1);
    return x;
  }
  const double s = std::sqrt(mean), d = 6 * mean * mean;
  const int64_t l = int64_t(mean - 1.1484);
  const double omega = .3989423 / s, b1 = .4166667E-1 / mean, b2 = .3 * b1 * b1, c3 = .1428571 * b1 * b2;
  const double c2 = b2 - 15. * c3, c1 = b1 - 6. * b2 + 45. * c3, c0 = 1. - b1 + 3. * b2 - 15. * c3, c = .1069 / mean;
  double difmuk = 0, u = 0;
  const double gg = mean + s * normal(g, 0, 1);
  if (gg >= 0) {
    x = int64_t(gg);
    if (x >= l) return x;
    difmuk = mean - x;
    u = uniform(g, 0, 1);
    if (d * u >= difmuk * difmuk * difmuk) return x;
  }
  for (bool usingExp = false; true; usingExp = true) {
    double e = 0;
    if (usingExp || gg < 0) {
      double t;
      do {
        e = exponential(g, 1.0);
        u = uniform(g, 0, 1);
        u += u - 1;
        t = 1.8 + (u < 0 ? -e : e);
      } while (t <= -.6744);
      x = int64_t(mean + s * t);
      difmuk = mean - x;
      usingExp = true;
    }
    double px, py;
    if (x < 10) {
      static const int64_t factorial[] = {1, 1, 2, 6, 24, 120, 720, 5040, 40320, 362880};
      px = -mean;
      py = std::pow(mean, double(x)) / factorial[x];
    } else {
      double del = .8333333E-1 / x;
      del -= 4.8 * del * del * del;
      const double v = difmuk / x;
      if (std::abs(v) > 0.25)
        px = x * std::log(1 + v) - difmuk - del;
      else
        px = x * v * v *
                 (((((((.1250060 * v + -.1384794) * v + .1421878) * v + -.1661269) * v + .2000118) * v + -.2500068) * v +
                   .3333333) * v + -.5) -
             del;
      py = .3989423 / std::sqrt(double(x));
    }
    const double r = (0.5 - difmuk) / s, r2 = r * r, fx = -0.5 * r2;
    const double fy = omega * (((c3 * r2 + c2) * r2 + c1) * r2 + c0);
    if (usingExp) {
      if (c * std::abs(u) <= py * std::exp(px + e) - fy * std::exp(fx + e)) break;
    } else {
      if (fy - u * fy <= py * std::exp(px - fx)) break;
    }
  }
  return x;
}

int64_t negativeBinomial(Generator& g, int64_t k, double p) {
  if (k <= 21 * p) {
    int64_t failures = 0, successes = 0;
    while (successes < k) {
      if (bernoulli(g, p)) ++successes;
      else ++failures;
    }
    return failures;
  }
  const double mean = gamma(g, double(k), (1 - p) / p);
  return poisson(g, mean);
}

// The weights' absolute values, normalised in order, summed over all but the last; the index of
// the first sum above a uniform draw. One weight: no sums, index 0 (the draw is still made).
int64_t discrete(Generator& g, int count, const double* weights) {
  std::vector<double> w(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) w[size_t(i)] = std::fabs(weights[i]);
  std::vector<double> sums;
  if (count > 1) {
    double total = 0.0;
    for (double x : w) total += x;
    for (double& x : w) x /= total;
    sums.resize(w.size() - 1);
    double acc = 0;
    for (size_t i = 0; i + 1 < w.size(); ++i) sums[i] = acc += w[i];
  }
  const double u = uniform(g, 0, 1);
  return int64_t(std::upper_bound(sums.begin(), sums.end(), u) - sums.begin());
}

double probability(double p) { return p < 0.0 ? 0.0 : (p > 1.0 ? 1.0 : p); }
double positive(double p) { return p > 0.0 ? p : std::numeric_limits<double>::epsilon(); }
double degrees(double n) { return n >= 1.0 ? std::floor(n) : 1.0; }
// A trial count as Context Free passes one: the number cast to an unsigned 64-bit integer, then
// taken as a signed one, at least 1.
int64_t trials(double n) {
  const int64_t t = int64_t(uint64_t(n));
  return t < 1 ? 1 : t;
}

}  // namespace

double distribution(uint64_t& state, int kind, int count, const double* a) {
  Generator g{state};
  switch (kind) {
    case __cf_RandExponential: return exponential(g, positive(a[0]));
    case __cf_RandGamma: return gamma(g, positive(a[0]), positive(a[1]));
    case __cf_RandWeibull: return positive(a[1]) * std::pow(exponential(g, 1.0), 1 / positive(a[0]));
    case __cf_RandExtremeValue: return a[0] - positive(a[1]) * std::log(-std::log(1 - uniform(g, 0, 1)));
    case __cf_RandNormal: return normal(g, a[0], a[1]);
    case __cf_RandLogNormal: return std::exp(normal(g, a[0], a[1]));
    case __cf_RandChiSquared: return gamma(g, degrees(a[0]) / 2, 2);
    case __cf_RandCauchy:
      return a[0] + positive(a[1]) * std::tan(3.1415926535897932384626433832795 * uniform(g, 0, 1));
    case __cf_RandFisherF: {
      // The numerator's gamma is drawn first.
      const double m = degrees(a[0]), n = degrees(a[1]);
      const double gm = gamma(g, m * .5, 1);
      const double gn = gamma(g, n * .5, 1);
      return n * gm / (m * gn);
    }
    case __cf_RandStudentT: {
      // The normal deviate is drawn first.
      const double n = degrees(a[0]);
      const double z = normal(g, 0, 1);
      return z * std::sqrt(n / gamma(g, n * .5, 2));
    }
    case __cf_RandBernoulli: return bernoulli(g, probability(a[0])) ? 1.0 : 0.0;
    case __cf_RandBinomial: return std::floor(double(binomial(g, trials(a[0]), probability(a[1]))));
    case __cf_RandNegBinomial: return std::floor(double(negativeBinomial(g, trials(a[0]), probability(a[1]))));
    case __cf_RandPoisson: return std::floor(double(poisson(g, positive(a[0]))));
    case __cf_RandGeometric: return std::floor(double(negativeBinomial(g, 1, probability(a[0]))));
    case __cf_RandDiscrete: return double(discrete(g, count, a));
  }
  return 0;
}

}  // namespace lcjit::runtime::cfdg
