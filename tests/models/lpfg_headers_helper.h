// A model header that insists on lpfg's header, as research models' headers do.
#ifndef __LPFGALL_H__
#error lpfg_headers_helper.h must be included after lpfgall.h
#endif
static const int helper_value = 40;
