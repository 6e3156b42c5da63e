// SPDX-License-Identifier: Apache-2.0
// Exact orientation predicates on double coordinates: a floating-point filter (Shewchuk's
// static error bounds) and, where it cannot decide, exact expansion arithmetic.
#pragma once

#include <Eigen/Core>

namespace sf {

/// Sign of det[a - d; b - d; c - d] (rows), computed exactly for finite doubles whose products
/// neither overflow nor underflow (magnitudes within about 1e-100 .. 1e100, or 0): +1 when d
/// lies below the plane through a, b, c (seen so that a, b, c run counter-clockwise), -1 above,
/// 0 exactly on it. Non-finite or overflowing input gives 0 (not decided).
int orient3d(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
             const Eigen::Vector3d& d) noexcept;

/// Sign of det[a - c; b - c], exact: +1 when a, b, c turn counter-clockwise, -1 clockwise, 0
/// exactly collinear (non-finite or overflowing input: 0).
int orient2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) noexcept;

}  // namespace sf
