#include "gpl/halves.h"

#include <algorithm>

namespace gpl {

void Halves::whole(std::size_t bodies) {
    cut_ = false;
    side_.assign(bodies, kLeft);
    local_.resize(bodies);
    for (std::size_t i = 0; i < bodies; ++i) local_[i] = i;
    versions_[kLeft].assign(bodies, 0);
    statics_.clear();
}

void Halves::begin(const std::vector<Body>& bodies) {
    cut_ = true;
    side_.assign(bodies.size(), kNone);
    local_.assign(bodies.size(), 0);
    movable_.clear();
    statics_.clear();
}

void Halves::see(const std::vector<Body>& bodies, std::size_t i) {
    if (bodies[i].isStatic() || side_[i] != kNone) return;
    side_[i] = kLeft;  // seen; its side follows in finish()
    movable_.push_back(i);
}

void Halves::finish(const std::vector<Body>& bodies) {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    for (std::size_t k = 0; k < movable_.size(); ++k) {
        const Vec3& x = bodies[movable_[k]].position;
        lo = k == 0 ? x : lo.cwiseMin(x);
        hi = k == 0 ? x : hi.cwiseMax(x);
    }
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    along_.clear();
    for (const std::size_t i : movable_) along_.push_back(bodies[i].position[axis]);
    double median = 0.0;
    if (!along_.empty()) {
        const auto middle = along_.begin() + static_cast<std::ptrdiff_t>(along_.size() / 2);
        std::nth_element(along_.begin(), middle, along_.end());
        median = *middle;
    }
    for (int half : {kLeft, kRight}) versions_[half].clear();
    for (const std::size_t i : movable_) {
        const int s = bodies[i].position[axis] < median ? kLeft : kRight;
        side_[i] = s;
        local_[i] = versions_[s].size();
        versions_[s].push_back(0);
    }
}

void Halves::registerStatics(std::size_t a, std::size_t b) {
    if (part(a, b) == kMiddle) return;
    for (const std::size_t i : {a, b}) {
        if (side_[i] != kNone || std::find(statics_.begin(), statics_.end(), i) != statics_.end()) continue;
        local_[i] = statics_.size();
        statics_.push_back(i);
    }
}

void Halves::copyStatics(const std::vector<Body>& bodies) {
    for (int half : {kLeft, kRight}) {
        copies_[half].clear();
        for (const std::size_t i : statics_) copies_[half].push_back(bodies[i]);
        staticVersions_[half].assign(statics_.size(), 0);
    }
}

int Halves::part(std::size_t a, std::size_t b) const {
    if (!cut_) return kMiddle;
    const int sa = side_[a], sb = side_[b];
    return sa == kNone ? sb : sb == kNone ? sa : sa == sb ? sa : kMiddle;
}

Body& Halves::body(int part, std::size_t i, std::vector<Body>& bodies) {
    if (part != kMiddle && side_[i] == kNone) return copies_[part][local_[i]];
    return bodies[i];
}

std::uint32_t& Halves::version(int part, std::size_t i) {
    if (side_[i] == kNone) return part == kMiddle ? uncounted_ : staticVersions_[part][local_[i]];
    return versions_[side_[i]][local_[i]];
}

void Halves::mergeStatics(std::vector<Body>& bodies) {
    for (std::size_t s = 0; s < statics_.size(); ++s) {
        Body& body = bodies[statics_[s]];
        const Body& left = copies_[kLeft][s];
        const Body& right = copies_[kRight][s];
        const Vec3 x = (left.position - body.position) + (right.position - body.position);
        const Vec3 v = (left.velocity - body.velocity) + (right.velocity - body.velocity);
        const Vec3 w = (left.angularVelocity - body.angularVelocity) + (right.angularVelocity - body.angularVelocity);
        if (x.isZero(0.0) && v.isZero(0.0) && w.isZero(0.0)) continue;
        body.position += x;
        body.velocity += v;
        body.angularVelocity += w;
        for (int half : {kLeft, kRight}) {
            copies_[half][s] = body;
            ++staticVersions_[half][s];
        }
    }
}

}  // namespace gpl
