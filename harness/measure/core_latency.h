// How long a cache line takes to travel from one core to another and back: the price a worker
// pool pays at every hand-over between threads, and the fact about a machine that decides whether
// a second worker pays (fx2d/src/README.md, "Threads"). On the shared 2-core virtual machine Fx2D
// is developed on it moved between 60 and 600 ns within minutes, and the same build's two-worker
// step with it, from 0.8 to 1.8 times the one-worker step. A thread timing is read with it.
#pragma once

namespace fxbench {

// Two threads hand a flag back and forth; the median over batches of round trips, in nanoseconds.
// A thread that finds the flag not yet handed back spins, then yields, so the measurement ends
// within milliseconds even when the two threads share one core (it then measures the scheduler,
// microseconds). 0 on a machine with one hardware thread. Takes about a millisecond.
double measure_core_round_trip_ns();

}  // namespace fxbench
