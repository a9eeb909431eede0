#pragma once
// ParamsClass: binds a C++ parameter struct as a Python class with a keyword constructor (unknown names are a
// TypeError listing the fields) and a repr that lists every bound field, e.g.
// SteppingStonesSupervisorParams(max_steps=30, ...).
#include <memory>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>

namespace rome::python {

template <class T>
class ParamsClass {
 public:
  ParamsClass(pybind11::module_& m, const char* name, const char* doc)
      : class_(m, name, doc), name_(name), fields_(std::make_shared<std::vector<std::string>>()) {
    namespace py = pybind11;
    auto fields = fields_;
    std::string type_name = name_;
    class_.def(py::init([fields, type_name](const py::kwargs& kwargs) {
      T value;
      py::object self = py::cast(&value, py::return_value_policy::reference);
      for (const auto& [key, item] : kwargs) {
        const std::string k = py::str(key);
        bool known = false;
        for (const auto& f : *fields) known = known || f == k;
        if (!known) {
          std::string list;
          for (const auto& f : *fields) list += (list.empty() ? "" : ", ") + f;
          throw py::type_error(type_name + " has no field '" + k + "' (fields: " + list + ")");
        }
        self.attr(key) = item;
      }
      return value;
    }));
    class_.def("__repr__", [fields, type_name](const py::object& self) {
      std::string text = type_name + "(";
      for (size_t i = 0; i < fields->size(); ++i)
        text += (i ? ", " : "") + (*fields)[i] + "=" + std::string(py::str(py::repr(self.attr((*fields)[i].c_str()))));
      return text + ")";
    });
  }
  template <class F>
  ParamsClass& Field(const char* name, F T::*member, const char* doc = "") {
    class_.def_readwrite(name, member, doc);
    fields_->push_back(name);
    return *this;
  }
  pybind11::class_<T>& cls() { return class_; }

 private:
  pybind11::class_<T> class_;
  std::string name_;
  std::shared_ptr<std::vector<std::string>> fields_;
};

}  // namespace rome::python
