// Recorded history of full engine states, newest last, within a memory budget: when a new state
// does not fit, the oldest ones go.
#pragma once

#include <cstddef>
#include <deque>

#include "gpl/engine.h"

namespace gpl::viewer {

class History {
public:
    explicit History(std::size_t byteBudget) : budget_(byteBudget) {}
    void push(PhysicsEngine::State state);
    /// Takes the newest state out; false when there is none.
    bool pop(PhysicsEngine::State& state);
    void clear();
    std::size_t size() const { return states_.size(); }
    std::size_t bytes() const { return bytes_; }
    std::size_t budget() const { return budget_; }
    /// Approximate memory a state holds (bytes).
    static std::size_t bytesOf(const PhysicsEngine::State& state);

private:
    std::size_t budget_;
    std::size_t bytes_ = 0;
    std::deque<PhysicsEngine::State> states_;
};

}  // namespace gpl::viewer
