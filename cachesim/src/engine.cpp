// Replaced by the cache engine.
namespace nodetrace::cachesim {}
