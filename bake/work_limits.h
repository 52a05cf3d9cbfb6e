#pragma once
// What a request will cost, checked before the work starts: a setting that needs more memory
// than the machine has available, or more than a documented cap, is refused in a second with
// the setting's name and the estimate, instead of exhausting the machine or failing late with
// std::bad_alloc. The passes themselves keep their memory bounded whatever the ray counts
// (radiosity shots and HQ waves are traced in fixed-size chunks).

#include <cstdint>
#include <string>
#include <string_view>

namespace lb {

// Caps that no machine size lifts, with the reason for each.
// ~6 hours of radiosity rays at this machine's ~5 M rays/s; nothing converges slower than that.
inline constexpr uint64_t kMaxRadiosityRayBudget = 100'000'000'000;
// Patches (and about twice as many refined triangles, ~0.5 KB each with their bookkeeping):
// far past where the shooting converges (the 100,000-shot cap stops it long before).
inline constexpr double kMaxRadiosityPatches = 4e6;
// Per-pixel sample permutations hold 3 ints a sample per thread: 2^20 samples = 12 MB.
inline constexpr int kMaxSamplesPerPixel = 1 << 20;
// Final gather rays per shading point: 4096 already average a smooth field to ~1%; the
// per-point row permutation holds one int each.
inline constexpr int kMaxFinalGather = 4096;

// Bytes the kernel reports it can hand out now without swapping (MemAvailable); 0 if unknown.
uint64_t available_memory_bytes();

// The most memory this process has held resident so far (getrusage's ru_maxrss), bytes.
uint64_t peak_resident_bytes();

// "1.5 GiB", "320 MiB", "12 KiB".
std::string format_bytes(double bytes);

// Throws std::invalid_argument "WHAT needs about X, more than the Y this machine has available"
// when `bytes` exceeds what is available (nothing is checked when that is unknown).
void require_memory(std::string_view what, double bytes);

}  // namespace lb
