// Linked into every test program of the TSan build only (EPI_SERIAL_TBB, tools/test.sh): oneTBB
// is not instrumented, so TSan cannot see its task hand-offs and reports every parallel_for as a
// race. With TBB held to one thread its loops run on the calling thread, and what TSan checks is
// the threads epi makes itself: the asynchronous shader's worker against the frame loop.
#include <tbb/global_control.h>

namespace {
const tbb::global_control kSerialTbb(tbb::global_control::max_allowed_parallelism, 1);
}  // namespace
