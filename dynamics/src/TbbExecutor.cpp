// rgvc::TbbExecutor over tbb::task_arena and tbb::parallel_for (oneTBB's task scheduler: work stealing,
// a well-kept library doing what a hand-written thread pool would).
#include "rgvc/dynamics/TbbExecutor.hpp"

#include "rgvc/grid/Error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <string>

namespace rgvc {

struct TbbExecutor::Impl {
    tbb::task_arena arena;
    explicit Impl(int n) : arena(n == 0 ? tbb::task_arena::automatic : n) {}
};

TbbExecutor::TbbExecutor(int maxConcurrency) {
    if (maxConcurrency < 0 || maxConcurrency > 256)
        throw InvalidInput("maxConcurrency", "must be 0 (automatic) or in [1, 256], got " + std::to_string(maxConcurrency));
    m_impl = std::make_unique<Impl>(maxConcurrency);
    m_impl->arena.initialize();
}

TbbExecutor::~TbbExecutor() = default;

void TbbExecutor::parallelFor(std::size_t count, const std::function<void(std::size_t)>& task) {
    m_impl->arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) task(i);
        }, tbb::simple_partitioner());
    });
}

int TbbExecutor::concurrency() const { return m_impl->arena.max_concurrency(); }

} // namespace rgvc
