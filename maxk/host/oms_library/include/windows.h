/* A small stand-in for <windows.h> on systems that have none (Linux, macOS): only the
 * types and calling-convention words that code written for the vendor's Windows motion
 * library uses, so such code compiles with `-I` pointing here and no other change.
 * It is not the Windows API; on Windows the compiler's own <windows.h> is used instead. */
#ifndef MAXK_WINDOWS_COMPAT_H
#define MAXK_WINDOWS_COMPAT_H

#if defined(_WIN32)
#include_next <windows.h>
#else

#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <strings.h>

typedef void *HANDLE;
typedef HANDLE *PHANDLE;
typedef char *LPSTR;
typedef const char *LPCSTR;
typedef char CHAR;
typedef char TCHAR;
typedef TCHAR *LPTSTR;
typedef const TCHAR *LPCTSTR;
typedef int BOOL;
typedef int INT;
typedef unsigned int UINT;
typedef unsigned char BYTE;
typedef unsigned short WORD;
typedef uint32_t DWORD;
typedef long LONG;
typedef unsigned long ULONG;
typedef LONG *PLONG;
typedef LONG *LPLONG;
typedef DWORD *LPDWORD;
typedef void VOID;
typedef void *LPVOID;
typedef short SHORT;
typedef float FLOAT;
typedef double DOUBLE;

#ifndef TRUE
#define TRUE 1
#endif
#ifndef FALSE
#define FALSE 0
#endif
#ifndef NULL
#define NULL ((void *)0)
#endif
#define INVALID_HANDLE_VALUE ((HANDLE)(intptr_t)-1)
#define MAX_PATH 260

/* Calling conventions and import/export words mean nothing on these systems. */
#define _stdcall
#define __stdcall
#define _cdecl
#define __cdecl
#define WINAPI
#define APIENTRY
#define CALLBACK
#define PASCAL
#define __declspec(x)
#define _TEXT(s) s
#define TEXT(s) s
#define _T(s) s

/* Helpers legacy programs lean on. */
#define ZeroMemory(p, n) memset((p), 0, (n))
#define lstrlen(s) ((int)strlen(s))
#define lstrcpy(d, s) strcpy((d), (s))
#define lstrcat(d, s) strcat((d), (s))
#define lstrcmp(a, b) strcmp((a), (b))
#define _strnicmp strncasecmp
#define _stricmp strcasecmp
#define stricmp strcasecmp
#define strnicmp strncasecmp

/* Sleep and GetTickCount live in libOmsMAXkMC, so they work in strict ISO C modes
 * (-ansi) where the POSIX clock calls are hidden. */
#ifdef __cplusplus
extern "C" {
#endif
void OmsCompatSleep(DWORD ms);
DWORD OmsCompatTickCount(void);
#ifdef __cplusplus
}
#endif
#define Sleep(ms) OmsCompatSleep((DWORD)(ms))
#define GetTickCount() OmsCompatTickCount()

#endif /* _WIN32 */
#endif /* MAXK_WINDOWS_COMPAT_H */
