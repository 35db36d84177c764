#pragma once
// Counts the heap allocations of the test program that includes this header (once): glibc
// lets the executable's malloc win, so g_mallocs counts every malloc, realloc and calloc.
#include <atomic>
#include <cstddef>

namespace { std::atomic<long> g_mallocs{0}; }
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* malloc(std::size_t n) { g_mallocs.fetch_add(1, std::memory_order_relaxed); return __libc_malloc(n); }
extern "C" void* realloc(void* p, std::size_t n) { g_mallocs.fetch_add(1, std::memory_order_relaxed); return __libc_realloc(p, n); }
extern "C" void* calloc(std::size_t a, std::size_t b) { g_mallocs.fetch_add(1, std::memory_order_relaxed); return __libc_calloc(a, b); }
