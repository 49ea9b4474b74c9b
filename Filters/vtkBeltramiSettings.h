// One source for each setting of the VTK filters.
//
// Enumerations: the filters' int constants (what Python and the ParaView XML
// use) are the values of the core's enum classes, joined by a cast.  Each
// adapter states the pairs with BELTRAMI_SAME_ENUM, so a change on either
// side fails to compile; the XML's EnumerationDomain values and defaults are
// checked against the filters by the test Python.PluginXMLMatchesFilters.
//
// Defaults: a filter whose settings mirror a core option struct lists the
// pairs once, in a function that copies them in either direction with
// BeltramiCopySetting: from the core's default-constructed options in the
// filter's constructor, to the core's options when it runs.  Not wrapped.
#ifndef vtkBeltramiSettings_h
#define vtkBeltramiSettings_h

#define BELTRAMI_SAME_ENUM(vtkConstant, coreEnumerator)                                          \
  static_assert(static_cast<int>(vtkConstant) == static_cast<int>(coreEnumerator),               \
    #vtkConstant " must equal " #coreEnumerator)

/// Which way BeltramiCopySetting copies.
enum class vtkBeltramiCopy
{
  ToCore,
  FromCore
};

/// Copies between a filter's setting and the core option it mirrors (ints and
/// enum classes by a cast: BELTRAMI_SAME_ENUM checks the values).
template <typename Setting, typename Option>
void BeltramiCopySetting(Setting& setting, Option& option, vtkBeltramiCopy direction)
{
  if (direction == vtkBeltramiCopy::ToCore)
  {
    option = static_cast<Option>(setting);
  }
  else
  {
    setting = static_cast<Setting>(option);
  }
}

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiSettings.h
