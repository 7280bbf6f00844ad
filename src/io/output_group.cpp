// OutputGroup: temporary files held under guard, renamed together with signals held.
#include "io/output_group.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/error.hpp"
#include "io/output_check.hpp"
#include "io/temporary_files.hpp"

namespace lidarscout::io {

struct OutputGroup::Entry {
    std::string temp, target;
    TemporaryFileGuard guard{temp};
};

OutputGroup::OutputGroup() = default;

OutputGroup::~OutputGroup() {
    if (committed_) return;
    for (const auto& e : entries_) std::remove(e->temp.c_str());
}

void OutputGroup::add(std::string temp, std::string target) {
    refuse_protected_input(target);
    for (const auto& e : entries_) {
        if (e->target == target || e->temp == temp) {
            throw Error(target, std::nullopt, "written twice in one output set (internal error)");
        }
    }
    entries_.push_back(std::unique_ptr<Entry>(new Entry{std::move(temp), std::move(target)}));
}

const std::string& OutputGroup::path_of(const std::string& target) const {
    for (const auto& e : entries_) {
        if (e->target == target) return e->temp;
    }
    return target;
}

void OutputGroup::commit() {
    const SignalHold hold;
    for (const auto& e : entries_) {
        if (std::rename(e->temp.c_str(), e->target.c_str()) != 0) {
            throw Error(e->target, std::nullopt, std::string("cannot rename the temporary file: ") +
                                                     std::strerror(errno));
        }
    }
    committed_ = true;
    entries_.clear();  // the guards go before the hold ends: a held signal removes nothing renamed
}

}  // namespace lidarscout::io
