// Single-producer single-consumer queue of fixed capacity: the hand-over
// between the real-time thread and the communication thread. Boost's
// lock-free spsc_queue with its capacity given at construction: the storage is
// allocated once there, push() and pop() never allocate (they copy into and
// out of that storage), are wait-free, and fail when full / empty
// (tests/firmware: TickAndReceiveAllocateNothingAfterWarmUp).
#pragma once

#include <boost/lockfree/spsc_queue.hpp>

namespace gimbalsim::firmware {

template <class T>
using SpscRing = boost::lockfree::spsc_queue<T>;

}  // namespace gimbalsim::firmware
