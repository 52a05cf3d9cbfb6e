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

// Bytes this process may plan to use: the least of the kernel's MemAvailable (what it can hand
// out without swapping), the cgroup's memory.max less its usage (a Slurm task's --mem, a
// Kubernetes limit: exceeding it gets the process killed, not slowed) and the environment's
// LIGHTBAKE_MAX_MEMORY (a farm task's share; throws std::invalid_argument if malformed).
// 0 if none is known.
uint64_t available_memory_bytes();

// "8G", "512M", "64K", "1000000": bytes, suffixes powers of 1024. Throws std::invalid_argument.
uint64_t parse_memory_size(std::string_view text);

// What a bake of `triangles` triangles holds at its peak, bytes, from the big level's
// measurements (docs/speed-accuracy.md, "Memory"): a fixed part (libraries, the light and
// patch tables of a small scene) and a part per triangle (mesh, Embree's BVH, atlas charts,
// radiosity's refined triangles). The atlas's texels (at most 2048^2, ~0.5 GiB) and the
// radiosity patches (checked when they are known) are not in it.
double estimate_bake_bytes(uint64_t triangles);

// The most memory this process has held resident so far (getrusage's ru_maxrss), bytes.
uint64_t peak_resident_bytes();

// Hands the heap's freed memory back to the system (glibc's malloc_trim; nothing elsewhere).
// Worker threads allocate from malloc arenas of their own, which keep what they free: after
// pass 1's light-group sums (small blocks, threads') and between the EXRs a bake writes
// (OpenEXR's threads) a 4-group bake held ~90 MiB more resident each time without it. It does
// not release the top of a worker thread's heap: `lightbake` lowers glibc's trim threshold
// (mallopt in app/main.cpp) so that is returned as it is freed.
void release_freed_memory();

// "1.5 GiB", "320 MiB", "12 KiB".
std::string format_bytes(double bytes);

// Throws std::invalid_argument "WHAT needs about X, more than the Y available to it (...)"
// when `bytes` exceeds what is available (nothing is checked when that is unknown).
void require_memory(std::string_view what, double bytes);

}  // namespace lb
