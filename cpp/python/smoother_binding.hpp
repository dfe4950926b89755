// The smoothed batch run shared by the filter bindings: the forward batch loop with the
// smoother's record as its observer, then the backward pass (core/smoother.hpp), both with the
// GIL released; the record's memory is taken once, before the loop, with the GIL held (a
// MemoryError when it cannot be had).
#pragma once

#include <new>

#include <quatnav/core/smoother.hpp>

#include "common.hpp"

namespace quatnav_py {

inline const char* smoother_result_str(int r) {
  switch (r) {
    case 0: return "ok";
    case 1: return "nothing_to_smooth";
    case 2: return "out_of_capacity";
    default: return "not_reserved";
  }
}

/// Run forward(smoother) (the batch loop, reporting to the smoother) and the backward pass into
/// out(k, record, P^s). n samples, at most max_epochs of them changed by a measurement.
/// Returns {"status", "bytes", "records", "capacity", "segment", "record_bytes"}.
template <class Model, class Forward, class Out>
py::dict run_smoothed(Model& model, std::size_t n, std::size_t max_epochs, std::size_t segment, Forward&& forward,
                      Out&& out) {
  quatnav::RtsSmoother<Model> sm(model);
  if (!sm.reserve(n, max_epochs, segment)) throw std::bad_alloc();
  typename quatnav::RtsSmoother<Model>::Result r;
  {
    py::gil_scoped_release release;
    forward(sm);
    r = sm.smooth(out);
  }
  py::dict info;
  info["status"] = smoother_result_str(int(r));
  info["bytes"] = sm.bytes();
  info["records"] = sm.records();
  info["capacity"] = sm.capacity();
  info["segment"] = sm.segment();
  info["record_bytes"] = quatnav::RtsSmoother<Model>::record_bytes();
  return info;
}

}  // namespace quatnav_py
