// Every allocation of a test program counted, so that a test can see that a step makes none: the
// replaceable operator new counts into `allocations`. A replaced operator new is defined once per
// program, so one source file of a program includes this header (each test program is one file).
// The replacements pair malloc with free, the nothrow forms too (std::stable_sort's buffer comes
// from them): under AddressSanitizer, which replaces every form, a form left to it would allocate
// what these free. GCC, seeing free where a delete expression is inlined, warns.
#pragma once

#include <cstdlib>
#include <new>

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

/// How many times operator new has been called in this program.
inline long allocations = 0;

void* operator new(std::size_t size) {
    ++allocations;
    if (void* memory = std::malloc(size > 0 ? size : 1)) return memory;
    throw std::bad_alloc();
}
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    ++allocations;
    return std::malloc(size > 0 ? size : 1);
}
void operator delete(void* memory, const std::nothrow_t&) noexcept { std::free(memory); }
