// rgvc::TbbExecutor: a TaskExecutor (Culler.hpp) over a TBB task arena of its own (Debian's libtbb-dev),
// what Culler::cullViews uses when it is given no executor. No TBB type reaches this header: an
// application that runs TBB itself passes its own executor, or this one, sized as it likes.
#pragma once

#include "rgvc/dynamics/Culler.hpp"

#include <memory>

namespace rgvc {

class TbbExecutor final : public TaskExecutor {
public:
    /// @param maxConcurrency [Threads] [Limit] 0 (TBB's default: every core the process may use) or
    ///        1..256. The arena's threads are TBB's; the calling thread joins in.
    /// @throws InvalidInput on a value out of range ("maxConcurrency").
    explicit TbbExecutor(int maxConcurrency = 0);
    ~TbbExecutor() override;
    TbbExecutor(const TbbExecutor&) = delete;
    TbbExecutor& operator=(const TbbExecutor&) = delete;

    /// One TBB task per index, run in the arena (tbb::parallel_for with a grain of one).
    void parallelFor(std::size_t count, const std::function<void(std::size_t)>& task) override;
    /// [Threads] the arena's concurrency.
    int concurrency() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace rgvc
