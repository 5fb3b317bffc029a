#include "convert.h"

#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <thread>

namespace gyrocomp::python {

std::span<const double> AsSpan(const DoubleArray& a, const char* name) {
  if (a.ndim() != 1) {
    throw py::value_error(std::string(name) + ": expected a 1-D array, got " + std::to_string(a.ndim()) + " dimensions");
  }
  return {a.data(), static_cast<std::size_t>(a.shape(0))};
}

template <class T>
py::array_t<T> MoveToNumpy(std::vector<T>&& v) {
  auto* owned = new std::vector<T>(std::move(v));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>({owned->size()}, {sizeof(T)}, owned->data(), owner);
}

py::array_t<double> ToNumpy(std::vector<double>&& v) { return MoveToNumpy(std::move(v)); }
py::array_t<std::int64_t> ToNumpy(std::vector<std::int64_t>&& v) { return MoveToNumpy(std::move(v)); }

py::array_t<double> ToNumpy2d(const std::vector<std::vector<double>>& rows) {
  const std::size_t k = rows.size(), n = rows.empty() ? 0 : rows.front().size();
  py::array_t<double> out({k, n});
  double* p = out.mutable_data();
  for (std::size_t i = 0; i < k; ++i) std::memcpy(p + i * n, rows[i].data(), n * sizeof(double));
  return out;
}

void Raise(const Error& error) {
  switch (error.kind) {
    case ErrorKind::kInvalidInput:
    case ErrorKind::kInvalidArgument:
    case ErrorKind::kUnsupported:
      throw py::value_error(error.message);
    case ErrorKind::kIo:
    case ErrorKind::kDidNotConverge:
    case ErrorKind::kInternal:
      break;
  }
  throw std::runtime_error(error.message);  // pybind11: RuntimeError
}

py::object Kwargs::Take(const char* name) {
  if (!kw_.contains(name)) return py::none();
  used_.insert(name);
  return kw_[name];
}

py::dict Kwargs::Nested(const char* name) {
  py::object v = Take(name);
  if (v.is_none()) return {};
  if (!py::isinstance<py::dict>(v)) throw py::type_error(fn_ + "(): keyword '" + name + "' must be a dict");
  return v.cast<py::dict>();
}

void Kwargs::Done() const {
  for (auto item : kw_) {
    const std::string key = py::str(item.first);
    if (!used_.count(key)) throw py::type_error(fn_ + "() got an unexpected keyword argument '" + key + "'");
  }
}

void Hooks::Poll(const std::string& stage, double fraction) const {
  if (token_ != nullptr && token_->cancelled()) throw Cancelled();
  if (progress_.is_none()) return;
  py::gil_scoped_acquire gil;
  progress_(stage, fraction);
}

void LongCall::Wait(const std::function<void()>& work) {
  std::mutex mu;
  std::condition_variable cv;
  bool done = false;
  PyObject *type = nullptr, *value = nullptr, *traceback = nullptr;  // a signal handler's exception
  if (caller_ != nullptr && caller_->cancelled()) stop_.Cancel();  // the library polls on entry
  {
    py::gil_scoped_release release;
    std::thread worker([&] {
      work();
      const std::lock_guard<std::mutex> lock(mu);
      done = true;
      cv.notify_all();
    });
    std::unique_lock<std::mutex> lock(mu);
    while (!cv.wait_for(lock, std::chrono::milliseconds(kPollIntervalMs), [&] { return done; })) {
      lock.unlock();
      if (caller_ != nullptr && caller_->cancelled()) stop_.Cancel();
      if (type == nullptr) {
        const py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) {
          PyErr_Fetch(&type, &value, &traceback);
          stop_.Cancel();
        }
      }
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (type != nullptr) {
    PyErr_Restore(type, value, traceback);
    throw py::error_already_set();
  }
}

}  // namespace gyrocomp::python
