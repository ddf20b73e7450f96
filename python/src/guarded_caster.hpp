// Arguments and `self` of the package's classes are checked before use: an
// instance made by `Cls.__new__(Cls)` without `__init__` holds no object, and
// pybind11 would hand the method uninitialised memory (a crash). Every class
// bound here gets this caster, so such an instance raises TypeError instead.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

namespace gimbalsim::py {

template <class T>
struct GuardedCaster : pybind11::detail::type_caster_base<T> {
  bool load(pybind11::handle src, bool convert) {
    namespace pyd = pybind11::detail;
    const pyd::type_info* info = pyd::get_type_info(typeid(T));
    if (src && info && PyObject_TypeCheck(src.ptr(), info->type)) {
      auto* inst = reinterpret_cast<pyd::instance*>(src.ptr());
      if (!inst->get_value_and_holder(info).holder_constructed()) {
        const std::string name = info->type->tp_name;
        throw pybind11::type_error(name + " object is not initialised (made by __new__ without __init__); "
                                          "create it through the gimbalsim API");
      }
    }
    return pyd::type_caster_base<T>::load(src, convert);
  }
};

}  // namespace gimbalsim::py

/// Declares the guarded caster for a bound class T (at global scope, before T is used).
#define GIMBALSIM_GUARDED_CASTER(T)                                  \
  namespace pybind11::detail {                                       \
  template <>                                                        \
  struct type_caster<T> : ::gimbalsim::py::GuardedCaster<T> {};      \
  }
