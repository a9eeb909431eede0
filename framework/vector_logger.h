#pragma once
// VectorLogger: records its inputs over time and writes them as CSV with a header naming every column.
//
// inputs: one per logged signal, each named by the user (e.g. "plant.q"), sizes as declared; a signal may also be a
//         typed port carrying an int or a double (e.g. a contact mode), logged as one column.
// Columns are named "<signal>.<element>" when the signal has element names (e.g. "plant.com.z"), else
// "<signal>[i]"; ColumnIndex() finds a column by name, so a user reads the log by name, not by position.
// Sampling: every `period_s` (periodic publish), or, with period_s = 0, at initialisation, after every guard
// event and at every periodic sample time of the diagram ("every event and sample").

#include <string>
#include <vector>

#include "framework/diagram.h"
#include "framework/system.h"

namespace rome {

struct LoggedSignal {
  std::string name;  ///< Input port name, also the column prefix.
  int size = 0;
  std::vector<std::string>
      element_names;  ///< Optional element names (size entries): columns name.element; default name[i].
  const std::type_info* scalar_type =
      nullptr;  ///< typeid(int) or typeid(double) for a typed scalar port (size 1); nullptr: vector
};

struct LogData {
  std::vector<double> times;
  std::vector<Eigen::VectorXd> samples;  ///< One stacked vector of all inputs per sample.
};

class VectorLogger final : public LeafSystem {
 public:
  VectorLogger(std::string name, std::vector<LoggedSignal> signals, double period_s);

  const LogData& log(const LeafContext& context) const { return context.scratch<LogData>(); }
  /// Column names, starting with "time".
  std::vector<std::string> ColumnNames() const;
  /// Index of the named column in each sample vector (LogData::samples; "time" is not in them). An error naming the
  /// logger and the column, with the columns of the same signal, if there is no such column.
  int ColumnIndex(const std::string& column) const;
  /// The log as CSV text: a header of the column names (CSV-escaped), then one row per sample.
  std::string CsvText(const LeafContext& context) const;
  /// Writes CsvText atomically (framework/files.h); std::runtime_error naming the file if it cannot be written, and
  /// then an existing file keeps its old content.
  void WriteCsv(const LeafContext& context, const std::string& path) const;

 protected:
  std::any AllocateScratch() const override { return LogData{}; }

 private:
  EventStatus Record(const LeafContext& context) const;
  std::vector<LoggedSignal> signals_;
  int total_size_ = 0;
};

/// Adds a VectorLogger named `name` to `builder` and connects each (system, output port) to it.
/// Signals are named "<system>.<port>".
VectorLogger* AddVectorLogger(DiagramBuilder& builder, const std::string& name,
                              const std::vector<std::pair<std::string, std::string>>& ports, double period_s);

}  // namespace rome
