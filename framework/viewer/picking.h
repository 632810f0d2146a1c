// Picking: which body a ray from the camera hits first. Spheres and boxes can be picked; planes
// cannot (they would catch every click that misses).
#pragma once

#include <optional>
#include <vector>

#include "camera.h"
#include "gpl/body.h"

namespace gpl::viewer {

/// Distance along the ray to where it enters the body, if it hits it (m).
std::optional<double> intersect(const Body& body, const Ray& ray);

struct Hit {
    std::size_t index;  ///< into the body list
    double distance;    ///< m along the ray
};
std::optional<Hit> pick(const std::vector<Body>& bodies, const Ray& ray);

}  // namespace gpl::viewer
