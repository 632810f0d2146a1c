#include "history.h"

namespace gpl::viewer {

std::size_t History::bytesOf(const PhysicsEngine::State& s) {
    std::size_t n = sizeof(s) + (s.previousPositions.capacity() + s.particlePositions.capacity() +
                                 s.particleVelocities.capacity()) * sizeof(Vec3) +
                    s.particleInverseMasses.capacity() * sizeof(double);
    for (const Body& b : s.bodies) n += sizeof(Body) + b.name.capacity();
    return n;
}

void History::push(PhysicsEngine::State state) {
    const std::size_t n = bytesOf(state);
    if (n > budget_) {
        clear();
        return;
    }
    while (!states_.empty() && bytes_ + n > budget_) {
        bytes_ -= bytesOf(states_.front());
        states_.pop_front();
    }
    bytes_ += n;
    states_.push_back(std::move(state));
}

bool History::pop(PhysicsEngine::State& state) {
    if (states_.empty()) return false;
    bytes_ -= bytesOf(states_.back());
    state = std::move(states_.back());
    states_.pop_back();
    return true;
}

void History::clear() {
    states_.clear();
    bytes_ = 0;
}

}  // namespace gpl::viewer
