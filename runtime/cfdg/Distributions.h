// Context Free's random distributions (rand::… and randint::… in a design), drawn from a random
// state as cfdg 3.4 draws them (Distributions.cpp).
#pragma once
#include <cstdint>

#include "runtime/include/lcjit/cfdg.h"

namespace lcjit::runtime::cfdg {

// One draw of distribution `kind` (a __cf_Distribution) with `count` arguments `args` (the
// weights of randint::discrete, else one or two), advancing `state` by the numbers it takes.
double distribution(uint64_t& state, int kind, int count, const double* args);

}  // namespace lcjit::runtime::cfdg
