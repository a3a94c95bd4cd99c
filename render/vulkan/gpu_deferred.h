// The list of deferred fragments (render/shaders/deferred_list.glsl): a volume draw or a cluster
// walk lists the fragments whose per-pixel set-up and sample loop a compute pass then runs, one
// thread a fragment — STSV's (stsv_samples.comp) and DCS's (wedge_samples.comp), one after the
// other for each light; DCS's walk lists each with its edge term (`terms`), which the samples
// pass then need not compute.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "render/options.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace stsv {

class Device;

/// The most fragments a list may hold (512 MiB of list).
inline constexpr std::uint64_t MAX_DEFERRED_FRAGMENTS = std::uint64_t(1) << 26;
/// Bytes of one listed fragment (a uvec2: pixel index, item).
inline constexpr std::uint64_t DEFERRED_FRAGMENT_BYTES = 8;

/// The fragments a frame's list holds at first: two a pixel (foliage with 16 k S-triangles lists
/// 1.5 a pixel), at most MAX_DEFERRED_FRAGMENTS; a frame that lists more grows the list and runs
/// again (DeferredFragments::growFor). The memory estimate of a frame counts the same.
inline std::uint64_t initialDeferredFragments(std::uint64_t pixels) {
    return std::min<std::uint64_t>(2 * pixels, MAX_DEFERRED_FRAGMENTS);
}

/// The list's count and (pixel index, item) pairs, and in a bitmask frame with STSV the mask
/// words stsv_samples.comp sets and stsv_merge.comp ORs into the images. Until a technique
/// uses it, one-element stand-ins for the descriptors.
class DeferredFragments {
  public:
    /// `initialCapacity`: the fragments the list holds once a technique uses it; `maxCapacity`
    /// the most it may grow to (0: MAX_DEFERRED_FRAGMENTS), never more than a storage buffer
    /// binding of the device addresses.
    DeferredFragments(const Device& device, const RenderOptions& options, std::uint64_t initialCapacity,
                      std::uint64_t maxCapacity = 0);
    /// The bindings of the list in a volume family's set (gpu_volumes_dh.h); the mask words are
    /// the STSV family's (gpu_stsv_dh.h).
    static std::vector<DescriptorBinding> bindings();
    void writeDescriptors(DescriptorSet& set) const;
    /// A technique lists fragments: the list gets its initial capacity, with `maskWords` the
    /// STSV samples' mask words of a bitmask frame, with `terms` a term record per fragment
    /// (which lowers maxCapacity() to what one binding of the records addresses). The
    /// descriptors must be written after.
    void use(bool maskWords, bool terms = false);
    std::uint64_t capacity() const { return m_capacity; }
    std::uint64_t maxCapacity() const { return m_maxCapacity; }
    /// After a frame whose draws listed `listed` fragments (for one light, at most): when that
    /// is more than the list held, some were lost, so the list grows to what the frame needed
    /// (a quarter more) and the caller renders the frame again (true; the descriptors must be
    /// written again). An Error past maxCapacity() (a walk takes its tiles in more parts
    /// instead: ClusterLists::splitFor).
    bool growFor(std::uint64_t listed);
    Buffer count;     ///< uvec4, x: fragments appended (past the end too)
    Buffer fragments; ///< uvec2 per fragment: pixel index, item (record or edge)
    Buffer maskWords; ///< lsMaskWordCount(N) words per pixel; else a stand-in
    Buffer terms;     ///< GPU_DEFERRED_TERM_TEXELS uvec4 per fragment when used; else a stand-in

  private:
    /// Room for `capacity` fragments, the old entries dropped.
    void resize(std::uint64_t capacity);
    const Device* m_device;
    std::uint64_t m_maxCapacity;
    std::uint64_t m_initialCapacity;
    std::uint64_t m_maskWordCount; ///< lsMaskWordCount(N) words per pixel of the frame
    std::uint64_t m_capacity = 0;
    bool m_maskWords = false;
    bool m_terms = false;
};

/// Workgroups of the compute passes over a list of up to `capacity` fragments of `samples`
/// samples each (64 threads; thread i takes the fragments i, i + groups · 64, ...): on a CPU
/// device every group is a task with its own start-up, and a few hundred keep its cores busy
/// (foliage 1000 plants at 512² on lavapipe: 4096 groups took 200-240 ms where 256 took
/// 130-180), but lavapipe also ends an invocation's loops after 65 535 iterations in all, so
/// there are enough groups that no thread takes more than SAMPLE_LOOP_BUDGET / (2·samples + 16)
/// fragments (a fragment loops up to about twice a sample: STSV's counters add a word's bits one
/// by one); a GPU needs some 10⁵ threads in flight.
std::uint32_t deferredSampleGroups(const Device& device, std::uint64_t capacity, int samples);

/// The loop iterations a thread of a pass over the deferred fragments may spend on them: half of
/// lavapipe's limit, the rest left to the shader's other loops.
inline constexpr std::uint64_t SAMPLE_LOOP_BUDGET = 32768;

} // namespace stsv
