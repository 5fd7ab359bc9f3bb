#include "basecamp/decode/value_text.hpp"

#include <algorithm>
#include <string>

#include "basecamp/decode/value_json.hpp"

namespace tgw::basecamp {

namespace {

bool all_scalars(const types::DecodedValue& list) {
    return std::all_of(list.items.begin(), list.items.end(),
                       [](const types::DecodedValue& v) { return v.is_scalar(); });
}

class TextWriter {
  public:
    TextWriter(std::ostream& out, std::size_t max_list_items) : out_(out), max_list_items_(max_list_items) {}

    /// The fields of `record` at column `indent`; the first line begins with `first_prefix` (a list item's
    /// "- ") instead of spaces when it is not empty.
    void record(const types::DecodedValue& record, std::size_t indent, const std::string& first_prefix = "") {
        for (std::size_t i = 0; i < record.fields.size(); ++i) {
            const std::string prefix = i == 0 && !first_prefix.empty() ? first_prefix : std::string(indent, ' ');
            field(prefix, indent, record.fields[i].first, record.fields[i].second);
        }
    }

  private:
    void field(const std::string& prefix, std::size_t indent, const std::string& name,
               const types::DecodedValue& value) {
        out_ << prefix << name << ':';
        if (inline_value(value)) {
            out_ << ' ';
            flow(value);
            out_ << '\n';
        } else if (value.kind == types::DecodedValue::Kind::record) {
            out_ << '\n';
            record(value, indent + 2);
        } else {
            out_ << '\n';
            for (const types::DecodedValue& item : value.items)
                list_item(item, indent);
        }
    }

    /// An element of a list of lists or of records, in block style at column `indent`.
    void list_item(const types::DecodedValue& item, std::size_t indent) {
        const std::string dash = std::string(indent, ' ') + "- ";
        if (inline_value(item)) {
            out_ << dash;
            flow(item);
            out_ << '\n';
        } else if (item.kind == types::DecodedValue::Kind::record) {
            record(item, indent + 2, dash);
        } else {
            out_ << std::string(indent, ' ') << "-\n";
            for (const types::DecodedValue& inner : item.items)
                list_item(inner, indent + 2);
        }
    }

    static bool inline_value(const types::DecodedValue& value) {
        if (value.kind == types::DecodedValue::Kind::record)
            return value.fields.empty();
        return value.is_scalar() || all_scalars(value);
    }

    void flow(const types::DecodedValue& value) {
        if (value.kind == types::DecodedValue::Kind::record) {
            out_ << "{}";
            return;
        }
        if (value.is_scalar()) {
            out_ << json_scalar(value);
            return;
        }
        out_ << '[';
        const std::size_t shown = std::min(value.items.size(), max_list_items_);
        for (std::size_t i = 0; i < shown; ++i)
            out_ << (i > 0 ? ", " : "") << json_scalar(value.items[i]);
        if (shown < value.items.size())
            out_ << (shown > 0 ? ", " : "") << "'... " << value.items.size() - shown << " more'";
        out_ << ']';
    }

    std::ostream& out_;
    const std::size_t max_list_items_;
};

}  // namespace

void write_text(std::ostream& out, const types::DecodedValue& value, std::size_t max_list_items) {
    TextWriter writer(out, max_list_items);
    if (value.kind == types::DecodedValue::Kind::record) {
        writer.record(value, 0);
    } else {
        types::DecodedValue wrapper;
        wrapper.fields.emplace_back("value", value);
        writer.record(wrapper, 0);
    }
}

}  // namespace tgw::basecamp
