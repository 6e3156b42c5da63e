// Shared by the global-query tests: HIPs pressed into a patch surface along the normals of
// sampled patch points, whose distance to the surface is known not to exceed the depth.
#pragma once

#include <Eigen/Core>
#include <initializer_list>
#include <vector>

#include <smoothforce/sweep/sweep_sampling.h>

namespace sf::test {

/// A HIP pressed `depth` (m) into the patch surface along the normal of samples[sample]: that
/// patch point lies at exactly `depth` from it, with the HIP below it, so the nearest patch point
/// is no farther.
struct PressedHip {
  Eigen::Vector3d hip;
  double depth = 0;
  size_t sample = 0;
};

/// For each depth (x diag, m) in turn, every sample pressed in by it: depths.size() x
/// samples.size() HIPs.
inline std::vector<PressedHip> pressedHips(const std::vector<SurfaceSample>& samples,
                                           std::initializer_list<double> depths, double diag) {
  std::vector<PressedHip> out;
  out.reserve(depths.size() * samples.size());
  for (double depth : depths)
    for (size_t i = 0; i < samples.size(); ++i)
      out.push_back({samples[i].point - depth * diag * samples[i].normal, depth * diag, i});
  return out;
}

}  // namespace sf::test
