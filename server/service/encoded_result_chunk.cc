#include "server/service/encoded_result_chunk.h"

#include <google/protobuf/unknown_field_set.h>

namespace mbstream {

namespace {

std::string* AddField(v1::ResultChunk& message, int number) {
  return message.GetReflection()->MutableUnknownFields(&message)->AddLengthDelimited(number);
}

}  // namespace

void EncodedResultChunk::AddFrame(std::string_view serialized_frame) {
  AddField(message_, v1::ResultChunk::kFramesFieldNumber)->assign(serialized_frame);
  ++items_;
  bytes_ += serialized_frame.size();
}

void EncodedResultChunk::AddProbe(const v1::ProbeReport& probe) {
  std::string* field = AddField(message_, v1::ResultChunk::kProbesFieldNumber);
  probe.SerializeToString(field);
  ++items_;
  bytes_ += field->size();
}

void EncodedResultChunk::Clear() {
  message_.Clear();
  items_ = 0;
  bytes_ = 0;
}

}  // namespace mbstream
