#include "framework/vector_logger.h"

#include <iomanip>
#include <sstream>

#include "framework/files.h"
#include "framework/text.h"

namespace rome {

VectorLogger::VectorLogger(std::string name, std::vector<LoggedSignal> signals, double period_s)
    : LeafSystem(std::move(name)), signals_(std::move(signals)) {
  for (const auto& s : signals_) {
    if (!s.element_names.empty() && static_cast<int>(s.element_names.size()) != s.size)
      ThrowError("signal '" + s.name + "' has size " + std::to_string(s.size) + " but " +
                 std::to_string(s.element_names.size()) + " element names");
    if (s.scalar_type != nullptr) {
      if (*s.scalar_type != typeid(int) && *s.scalar_type != typeid(double))
        ThrowError("signal '" + s.name + "' is a typed port carrying " + DemangledTypeName(*s.scalar_type) +
                   "; only int and double typed ports can be logged");
      if (s.size != 1)
        ThrowError("signal '" + s.name + "' is a typed scalar port but has size " + std::to_string(s.size));
      DeclareAbstractInputPort(s.name, *s.scalar_type);
    } else {
      DeclareInputPort(s.name, s.size);
    }
    total_size_ += s.size;
  }
  if (period_s > 0) {
    DeclarePeriodicPublish(period_s, 0.0, [this](const LeafContext& c) { return Record(c); });
  } else if (period_s == 0) {
    DeclareEventPublish([this](const LeafContext& c) { return Record(c); });
  } else {
    ThrowError("logging period must be >= 0 s, got " + std::to_string(period_s));
  }
}

EventStatus VectorLogger::Record(const LeafContext& context) const {
  LogData& data = context.scratch<LogData>();
  Eigen::VectorXd row(total_size_);
  int at = 0;
  for (int i = 0; i < num_input_ports(); ++i) {
    if (signals_[i].scalar_type == nullptr) {
      const Eigen::VectorXd& u = EvalInput(context, i);
      row.segment(at, u.size()) = u;
      at += static_cast<int>(u.size());
    } else {
      row[at++] = *signals_[i].scalar_type == typeid(int) ? static_cast<double>(EvalTypedInput<int>(context, i))
                                                          : EvalTypedInput<double>(context, i);
    }
  }
  data.times.push_back(context.time());
  data.samples.push_back(std::move(row));
  return EventStatus::Succeeded();
}

std::vector<std::string> VectorLogger::ColumnNames() const {
  std::vector<std::string> names{"time"};
  for (const auto& s : signals_)
    for (int i = 0; i < s.size; ++i) {
      if (!s.element_names.empty())
        names.push_back(s.name + "." + s.element_names[i]);
      else if (s.scalar_type != nullptr)
        names.push_back(s.name);
      else
        names.push_back(s.name + "[" + std::to_string(i) + "]");
    }
  return names;
}

int VectorLogger::ColumnIndex(const std::string& column) const {
  const std::vector<std::string> names = ColumnNames();
  for (size_t i = 1; i < names.size(); ++i)
    if (names[i] == column) return static_cast<int>(i) - 1;
  std::string near;
  const std::string prefix = column.substr(0, column.rfind('.'));
  for (size_t i = 1; i < names.size(); ++i)
    if (names[i].compare(0, prefix.size(), prefix) == 0) near += (near.empty() ? "" : ", ") + names[i];
  ThrowError("has no column '" + column + "'" + (near.empty() ? "" : " (columns of '" + prefix + "': " + near + ")"));
}

std::string VectorLogger::CsvText(const LeafContext& context) const {
  std::ostringstream out;
  const auto names = ColumnNames();
  for (size_t i = 0; i < names.size(); ++i)
    out << (i ? "," : "") << CsvCell(names[i]);  // names may come from a robot file
  out << "\n" << std::setprecision(12);
  const LogData& data = log(context);
  for (size_t k = 0; k < data.times.size(); ++k) {
    out << data.times[k];
    for (int i = 0; i < data.samples[k].size(); ++i) out << "," << data.samples[k][i];
    out << "\n";
  }
  return out.str();
}

void VectorLogger::WriteCsv(const LeafContext& context, const std::string& path) const {
  WriteFileAtomically(path, CsvText(context), "system '" + name() + "': log file");
}

VectorLogger* AddVectorLogger(DiagramBuilder& builder, const std::string& name,
                              const std::vector<std::pair<std::string, std::string>>& ports, double period_s) {
  std::vector<LoggedSignal> signals;
  for (const auto& [sys, port] : ports) {
    const System& s = builder.GetMutableSystem(sys);
    const PortInfo& info = s.output_port(s.GetOutputPortIndex(port));
    if (info.is_vector())
      signals.push_back({sys + "." + port, info.size, info.element_names, nullptr});
    else
      signals.push_back({sys + "." + port, 1, {}, info.value_type});
  }
  auto* logger = builder.AddSystem(std::make_unique<VectorLogger>(name, signals, period_s));
  for (const auto& [sys, port] : ports) builder.Connect(sys, port, name, sys + "." + port);
  return logger;
}

}  // namespace rome
