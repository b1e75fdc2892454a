// Velocity-only and semi-implicit Euler integration with drag (Eq. 7), checked before anything moves.
#include "cells/integrate.h"

#include <atomic>
#include <cmath>
#include <sstream>

#include "cells/simulation.h"
#include "core/errors.h"
#include "core/parallel.h"

namespace cellform::cells {

namespace {

// Problems in order of priority: a bad position explains the rest, so it is reported first.
enum Problem : std::uint64_t { kPosition = 0, kAcceleration = 1, kVelocity = 2, kSpeed = 3, kNone = 4 };

Vec3 new_velocity(const Cells& cells, const Params& params, std::size_t i) {
  const Vec3& a = cells.acceleration[i];
  if (params.integrator == Integrator::velocity) return params.drag.cwiseProduct(a);
  return params.drag.cwiseProduct(cells.velocity[i] + a * params.time_step);
}

const char* describe(const Vec3& v) {
  for (int k = 0; k < 3; ++k)
    if (std::isnan(v[k])) return "NaN";
  return "infinite";
}

void atomic_min(std::atomic<std::uint64_t>& target, std::uint64_t v) {
  std::uint64_t cur = target.load(std::memory_order_relaxed);
  while (v < cur && !target.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

void atomic_max(std::atomic<double>& target, double v) {
  double cur = target.load(std::memory_order_relaxed);
  while (v > cur && !target.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

}  // namespace

double integrate_and_measure(Cells& cells, const Params& params, std::uint64_t step, int threads) {
  const std::size_t n = cells.size();
  const double max_speed2 = params.max_speed * params.max_speed;

  // Pass 1: check every cell; the state stays untouched, so a throw leaves the last good step.
  std::atomic<std::uint64_t> worst{kNone << 32};
  std::atomic<double> fastest2{0.0};
  core::parallel_for(n, threads, [&](std::size_t begin, std::size_t end) {
    std::uint64_t local = kNone << 32;
    double local_fastest2 = 0;
    for (std::size_t i = begin; i < end; ++i) {
      std::uint64_t problem = kNone;
      if (!cells.position[i].allFinite()) {
        problem = kPosition;
      } else if (!cells.fixed[i]) {
        if (!cells.acceleration[i].allFinite()) {
          problem = kAcceleration;
        } else {
          const Vec3 v = new_velocity(cells, params, i);
          const double s2 = v.squaredNorm();
          if (!v.allFinite() || !(cells.position[i] + v * params.time_step).allFinite())
            problem = kVelocity;
          else if (s2 > max_speed2)
            problem = kSpeed;
          else
            local_fastest2 = std::max(local_fastest2, s2);
        }
      }
      // the whole range, not only its first problem: a later one of higher priority wins whatever the ranges
      // (a review: two threads named a NaN acceleration where one named a speed)
      if (problem != kNone) local = std::min(local, problem << 32 | i);
    }
    if (local != (kNone << 32)) atomic_min(worst, local);
    atomic_max(fastest2, local_fastest2);
  });

  const std::uint64_t w = worst.load();
  if ((w >> 32) != kNone) {
    const std::size_t i = w & 0xffffffffu;
    std::ostringstream msg;
    msg << "step " << step << ", cell " << cells.id[i] << ": ";
    switch (w >> 32) {
      case kPosition:
        msg << "position is " << describe(cells.position[i]);
        break;
      case kAcceleration:
        msg << "acceleration is " << describe(cells.acceleration[i]);
        break;
      case kVelocity:
        msg << "velocity is " << describe(new_velocity(cells, params, i));
        break;
      default: {
        // as many digits as tell the two apart (a speed just past the limit read "1e+06 exceeds 1e+06")
        const double speed = new_velocity(cells, params, i).norm();
        int digits = 6;
        auto text = [&](double x) {
          std::ostringstream t;
          t.precision(digits);
          t << x;
          return t.str();
        };
        while (digits < 17 && text(speed) == text(params.max_speed)) ++digits;
        msg << "speed " << text(speed) << " exceeds cells.max_speed = " << text(params.max_speed);
      }
    }
    msg << "; the simulation diverged (try a smaller cells.time_step, more drag or smaller force weights)";
    throw core::SimulationDiverged(msg.str());
  }

  // Pass 2: move (recomputing the same velocities bit for bit).
  core::parallel_for(n, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      if (cells.fixed[i]) {
        cells.velocity[i].setZero();
        continue;
      }
      const Vec3 v = new_velocity(cells, params, i);
      cells.velocity[i] = v;
      cells.position[i] += v * params.time_step;
    }
  });
  return std::sqrt(fastest2.load());
}

void integrate(Cells& cells, const Params& params, std::uint64_t step, int threads) {
  integrate_and_measure(cells, params, step, threads);
}

}  // namespace cellform::cells
