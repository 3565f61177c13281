// field_value_csv: the `field,value` table of tracetool info, tracer info and
// tracer scenes (--format csv).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "nodetrace/cli/csv_text.hpp"

namespace nodetrace::cli {
namespace {

// Issue 52 item 12: an empty object or array is {} or [] as in the JSON
// form, not null (which reads as a missing value); leaves keep their order
// and text is quoted only where CSV needs it.
TEST(CsvText, FieldValueTableKeepsEmptyObjectsAndArrays) {
  const auto object = nlohmann::json::parse(
      R"({"file":"t.din.zst","header":{"rays":{"left_out":{},"cast":["primary","shadow"]},"streams":[]},)"
      R"("note":"a, \"b\"","missing":null,"records":12})");
  EXPECT_EQ(field_value_csv(object),
            "field,value\n"
            "file,t.din.zst\n"
            "header.rays.cast.0,primary\n"
            "header.rays.cast.1,shadow\n"
            "header.rays.left_out,{}\n"
            "header.streams,[]\n"
            "missing,null\n"
            "note,\"a, \"\"b\"\"\"\n"
            "records,12\n");
}

}  // namespace
}  // namespace nodetrace::cli
