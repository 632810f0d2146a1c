// Owned<T>: one T of the owner's own, on the heap, copied with its owner (moved too: a copy). The
// engine holds its contact stages' state this way: engine.h then only names their types, and the
// files that include it (every hook file among them) compile none of those stages' headers.
#pragma once

namespace gpl {

template <class T>
class Owned {
public:
    Owned() : p_(new T()) {}
    Owned(const Owned& other) : p_(new T(*other.p_)) {}
    Owned& operator=(const Owned& other) {
        *p_ = *other.p_;
        return *this;
    }
    ~Owned() {
        static_assert(sizeof(T) > 0, "Owned<T> is made and ended where T is complete (the owner's .cpp file)");
        delete p_;
    }

    T& operator*() { return *p_; }
    const T& operator*() const { return *p_; }
    T* operator->() { return p_; }
    const T* operator->() const { return p_; }

private:
    T* p_;
};

}  // namespace gpl
