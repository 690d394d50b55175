/* OmsMAXkMC.h: the interface of the OMS MAXk motion-control library, written for the
 * maxk emulator (libOmsMAXkMC.so on Linux and macOS, OmsMAXkMC.dll on Windows).
 *
 * The names, parameter types, values and return codes are those of the vendor's library
 * (docs/oms-library.md lists where they come from), so a program written for the vendor's
 * OmsMAXkMC.dll compiles against this header unchanged. Every function but GetOmsHandle,
 * CloseOmsHandle, GetOmsDriverVersion, GetOmsDllVersion and OmsWait returns one of the
 * codes below. `long` is the platform's long, as in the vendor's header (32 bits on
 * Windows, 64 on LP64 systems): use `long` (ctypes: c_long) on the caller's side too. */
#ifndef MAXK_OMSMAXKMC_H
#define MAXK_OMSMAXKMC_H

#include <windows.h>

/* ---- return codes ------------------------------------------------------------------ */
#define SUCCESS 0
#define COMMAND_TIME_OUT 1       /* the board did not take the command in time */
#define RESPONSE_TIME_OUT 2      /* the board took it but did not answer in time */
#define INVALID_AXIS_SELECTION 3 /* an axis mask naming no axis, several, or absent axes */
#define MOVE_TIME_OUT 4          /* a ...Wait move was not done within its limit */
#define INVALID_PARAMETER 5      /* a value out of the range the library accepts */
#define INVALID_BIT_NUMBER 6     /* an I/O bit outside 0..15 */

/* ---- axis status (GetOmsAxisFlags) ------------------------------------------------- */
#define AXIS_DIRECTION 0x01 /* set while the axis is moving (or last moved) negative */
#define AXIS_DONE 0x02
#define AXIS_OVERTRAVEL 0x04
#define AXIS_HOME_SWITCH 0x08

/* ---- encoder status (GetOmsEncoderFlags) ------------------------------------------- */
#define SLIP_DETECT_ENABLED 0x01
#define POSITION_MAINTENANCE_ENABLED 0x02
#define AXIS_SLIPPED 0x04
#define AXIS_WITHIN_DEADBAND 0x08
#define ENCODER_AT_HOME 0x10

#define POSITIVE 0
#define NEGATIVE 1
#define MODE_OFF 0
#define MODE_ON 1
#define LOW 0
#define HIGH 1

/* ---- controller status (GetStatusFlags) -------------------------------------------- */
#define COMMAND_ERROR 0x01

/* ---- axis masks --------------------------------------------------------------------- */
#define OMS_X_AXIS 0x0001
#define OMS_Y_AXIS 0x0002
#define OMS_Z_AXIS 0x0004
#define OMS_T_AXIS 0x0008
#define OMS_U_AXIS 0x0010
#define OMS_V_AXIS 0x0020
#define OMS_R_AXIS 0x0040
#define OMS_S_AXIS 0x0080
#define OMS_W_AXIS 0x0100
#define OMS_K_AXIS 0x0200
#define OMS_ALL_AXES 0x03FF

/* ---- limit flags and sensors: minus X..K in bits 0..9, plus X..K in bits 10..19 ---- */
#define OMS_X_AXIS_NEG_LIMIT 0x00001
#define OMS_Y_AXIS_NEG_LIMIT 0x00002
#define OMS_Z_AXIS_NEG_LIMIT 0x00004
#define OMS_T_AXIS_NEG_LIMIT 0x00008
#define OMS_U_AXIS_NEG_LIMIT 0x00010
#define OMS_V_AXIS_NEG_LIMIT 0x00020
#define OMS_R_AXIS_NEG_LIMIT 0x00040
#define OMS_S_AXIS_NEG_LIMIT 0x00080
#define OMS_W_AXIS_NEG_LIMIT 0x00100
#define OMS_K_AXIS_NEG_LIMIT 0x00200
#define OMS_X_AXIS_POS_LIMIT 0x00400
#define OMS_Y_AXIS_POS_LIMIT 0x00800
#define OMS_Z_AXIS_POS_LIMIT 0x01000
#define OMS_T_AXIS_POS_LIMIT 0x02000
#define OMS_U_AXIS_POS_LIMIT 0x04000
#define OMS_V_AXIS_POS_LIMIT 0x08000
#define OMS_R_AXIS_POS_LIMIT 0x10000
#define OMS_S_AXIS_POS_LIMIT 0x20000
#define OMS_W_AXIS_POS_LIMIT 0x40000
#define OMS_K_AXIS_POS_LIMIT 0x80000

/* ---- general purpose I/O bits ------------------------------------------------------ */
#define BIT0 0x0001
#define BIT1 0x0002
#define BIT2 0x0004
#define BIT3 0x0008
#define BIT4 0x0010
#define BIT5 0x0020
#define BIT6 0x0040
#define BIT7 0x0080
#define BIT8 0x0100
#define BIT9 0x0200
#define BIT10 0x0400
#define BIT11 0x0800
#define BIT12 0x1000
#define BIT13 0x2000
#define BIT14 0x4000
#define BIT15 0x8000

#define MIN_VELOCITY 1
#define MAX_VELOCITY 4000000
#define MIN_ACCELERATION 1
#define MAX_ACCELERATION 8000000

/* One value per axis, X Y Z T U V R S W K. */
typedef struct {
    long X, Y, Z, T, U, V, R, S, W, K;
} AXES_DATA, *PAXES_DATA;

typedef struct {
    long Motor;
    long Encoder;
} AXIS_DATA;

typedef struct {
    AXIS_DATA X, Y, Z, T, U, V, R, S, W, K;
} POSITION_DATA, *PPOSITION_DATA;

typedef enum {
    OMS_BIG_CMD_BUFFER_MODE = 0,
    OMS_NORMAL_CMD_BUFFER_MODE = 1
} eOMSBuffMode;

/* DLLIMPORT: how the functions are declared to the caller. Building the library itself
 * (OMSMAXKMC_BUILD) exports them instead. */
#ifdef DLLIMPORT
#undef DLLIMPORT
#endif
#if defined(_WIN32)
#  ifdef OMSMAXKMC_BUILD
#    define OMS_LINKAGE __declspec(dllexport)
#  else
#    define OMS_LINKAGE __declspec(dllimport)
#  endif
#elif defined(__GNUC__)
#  define OMS_LINKAGE __attribute__((visibility("default")))
#else
#  define OMS_LINKAGE
#endif
#ifdef __cplusplus
#  define DLLIMPORT extern "C" OMS_LINKAGE
#else
#  define DLLIMPORT extern OMS_LINKAGE
#endif

/* ---- general ------------------------------------------------------------------------ */
DLLIMPORT HANDLE _stdcall GetOmsHandle(LPSTR name); /* "OmsMAXk1".."OmsMAXk16"; NULL: none */
DLLIMPORT void _stdcall CloseOmsHandle(HANDLE h);
DLLIMPORT long _stdcall ResetOmsController(HANDLE h);
DLLIMPORT long _stdcall SendOmsQueryCommand(HANDLE h, LPSTR command, LPSTR reply);
DLLIMPORT long _stdcall SendAndGetString(HANDLE h, LPSTR command, LPSTR reply);
DLLIMPORT long _stdcall SendOmsTextCommand(HANDLE h, LPSTR command);
DLLIMPORT long _stdcall SendString(HANDLE h, LPSTR command);
DLLIMPORT long _stdcall GetCmdBufferFree(HANDLE h); /* free bytes, not a return code */
DLLIMPORT long _stdcall GetOmsControllerDescription(HANDLE h, LPSTR text);
DLLIMPORT void _stdcall GetOmsDriverVersion(HANDLE h, LPSTR text);
DLLIMPORT void _stdcall GetOmsDllVersion(LPSTR text, long size);

/* ---- one axis (axis: one mask bit) ------------------------------------------------ */
DLLIMPORT long _stdcall MoveOmsAxisAbs(HANDLE h, long axis, long position);
DLLIMPORT long _stdcall MoveOmsAxisAbsWait(HANDLE h, long axis, long position, long ms);
DLLIMPORT long _stdcall MoveOmsAxisRel(HANDLE h, long axis, long distance);
DLLIMPORT long _stdcall MoveOmsAxisRelWait(HANDLE h, long axis, long distance, long ms);
DLLIMPORT long _stdcall MoveOmsAxisIndefinite(HANDLE h, long axis, long velocity);
DLLIMPORT long _stdcall MoveOmsAxisFractional(HANDLE h, long axis, double velocity);
DLLIMPORT long _stdcall MoveOmsAxisOneStep(HANDLE h, long axis, long direction);

/* ---- several axes: only the masked members of *data are used ----------------------- */
DLLIMPORT long _stdcall MoveOmsIndependentAbs(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall MoveOmsIndependentAbsWait(HANDLE h, long axes, PAXES_DATA data, long ms);
DLLIMPORT long _stdcall MoveOmsIndependentRel(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall MoveOmsIndependentRelWait(HANDLE h, long axes, PAXES_DATA data, long ms);
DLLIMPORT long _stdcall MoveOmsLinearAbs(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall MoveOmsLinearAbsWait(HANDLE h, long axes, PAXES_DATA data, long ms);
DLLIMPORT long _stdcall MoveOmsLinearRel(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall MoveOmsLinearRelWait(HANDLE h, long axes, PAXES_DATA data, long ms);
DLLIMPORT long _stdcall MoveOmsIndependentAbsMt(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall MoveOmsIndependentAbsMtWait(HANDLE h, long axes, PAXES_DATA data, long ms);
DLLIMPORT long _stdcall MoveOmsIndependentRelMt(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall MoveOmsIndependentRelMtWait(HANDLE h, long axes, PAXES_DATA data, long ms);
DLLIMPORT long _stdcall MoveOmsLinearAbsMt(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall MoveOmsLinearAbsMtWait(HANDLE h, long axes, PAXES_DATA data, long ms);
DLLIMPORT long _stdcall MoveOmsLinearRelMt(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall MoveOmsLinearRelMtWait(HANDLE h, long axes, PAXES_DATA data, long ms);

/* ---- stopping ----------------------------------------------------------------------- */
DLLIMPORT long _stdcall StopOmsAxis(HANDLE h, long axis);
DLLIMPORT long _stdcall StopAllOmsAxes(HANDLE h);
DLLIMPORT long _stdcall KillAllOmsMotion(HANDLE h);

/* ---- positions ---------------------------------------------------------------------- */
DLLIMPORT long _stdcall GetOmsAxisMotorPosition(HANDLE h, long axis, long *position);
DLLIMPORT long _stdcall GetOmsAxisEncoderPosition(HANDLE h, long axis, long *position);
DLLIMPORT long _stdcall GetOmsAxisAbsoluteEncoderPosition(HANDLE h, long axis, long *position);
DLLIMPORT long _stdcall GetSelectedOmsMotorPositions(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall GetSelectedOmsEncoderPositions(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall GetMotorPositions(HANDLE h, PAXES_DATA data);
DLLIMPORT long _stdcall GetEncoderPositions(HANDLE h, PAXES_DATA data);
DLLIMPORT long _stdcall GetAbsoluteEncoderPositions(HANDLE h, PAXES_DATA data);
DLLIMPORT long _stdcall GetPositionData(HANDLE h, PPOSITION_DATA data);

/* ---- position initialization ------------------------------------------------------- */
DLLIMPORT long _stdcall DefineOmsHomeAsSwitchClosed(HANDLE h, long axis);
DLLIMPORT long _stdcall DefineOmsHomeAsSwitchOpen(HANDLE h, long axis);
DLLIMPORT long _stdcall FindOmsAxisFwdLimit(HANDLE h, long axis, long velocity, long ms);
DLLIMPORT long _stdcall FindOmsAxisRevLimit(HANDLE h, long axis, long velocity, long ms);
DLLIMPORT long _stdcall HomeOmsAxisFwdUseEncoder(HANDLE h, long axis, long position);
DLLIMPORT long _stdcall HomeOmsAxisFwdUseEncoderWait(HANDLE h, long axis, long position, long ms);
DLLIMPORT long _stdcall HomeOmsAxisFwdUseSwitch(HANDLE h, long axis, long position);
DLLIMPORT long _stdcall HomeOmsAxisFwdUseSwitchWait(HANDLE h, long axis, long position, long ms);
DLLIMPORT long _stdcall HomeOmsAxisRevUseEncoder(HANDLE h, long axis, long position);
DLLIMPORT long _stdcall HomeOmsAxisRevUseEncoderWait(HANDLE h, long axis, long position, long ms);
DLLIMPORT long _stdcall HomeOmsAxisRevUseSwitch(HANDLE h, long axis, long position);
DLLIMPORT long _stdcall HomeOmsAxisRevUseSwitchWait(HANDLE h, long axis, long position, long ms);
DLLIMPORT long _stdcall SetOmsAxisPosition(HANDLE h, long axis, long position);

/* ---- velocity and acceleration ----------------------------------------------------- */
DLLIMPORT long _stdcall GetOmsAxisVelocity(HANDLE h, long axis, long *velocity);
DLLIMPORT long _stdcall GetSelectedOmsVelocities(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall SetOmsAxisBaseVelocity(HANDLE h, long axis, long velocity);
DLLIMPORT long _stdcall SetOmsAxisVelocity(HANDLE h, long axis, long velocity);
DLLIMPORT long _stdcall SetOmsAxisAcceleration(HANDLE h, long axis, long acceleration);
DLLIMPORT long _stdcall GetOmsAxisAcceleration(HANDLE h, long axis, long *acceleration);
DLLIMPORT long _stdcall GetSelectedOmsAccelerations(HANDLE h, long axes, PAXES_DATA data);
DLLIMPORT long _stdcall SelectOmsCosineRamp(HANDLE h, long axis);
DLLIMPORT long _stdcall SelectOmsLinearRamp(HANDLE h, long axis);
DLLIMPORT long _stdcall SelectOmsParabolicRamp(HANDLE h, long axis, long steps);
DLLIMPORT long _stdcall SelectOmsSCurveRamp(HANDLE h, long axis, long percent);

/* ---- flags (masks in, masks out) ---------------------------------------------------- */
DLLIMPORT long _stdcall GetOmsAxisDoneFlag(HANDLE h, long axis, BOOL *done);
DLLIMPORT long _stdcall GetDoneFlags(HANDLE h, long *axes);
DLLIMPORT long _stdcall GetAllOmsDoneFlags(HANDLE h, long *axes);
DLLIMPORT long _stdcall ClrDoneFlags(HANDLE h, long axes);
DLLIMPORT long _stdcall ClrOmsDoneFlags(HANDLE h, long axes);
DLLIMPORT long _stdcall GetLimitFlags(HANDLE h, long *limits);
DLLIMPORT long _stdcall GetAllOmsLimitFlags(HANDLE h, long *limits);
DLLIMPORT long _stdcall GetOmsAxisLimitFlag(HANDLE h, long axis, BOOL *limit);
DLLIMPORT long _stdcall ClrLimitFlags(HANDLE h, long limits);
DLLIMPORT long _stdcall ClrOmsLimitFlags(HANDLE h, long limits);
DLLIMPORT long _stdcall GetStatusFlags(HANDLE h, long *status);
DLLIMPORT long _stdcall GetOmsControllerFlags(HANDLE h, long *status);
DLLIMPORT long _stdcall ClrStatusFlags(HANDLE h, long status);
DLLIMPORT long _stdcall ClrOmsControllerFlags(HANDLE h, long status);
DLLIMPORT long _stdcall GetOmsAxisFlags(HANDLE h, long axis, long *flags);
DLLIMPORT long _stdcall GetOmsLimitSensors(HANDLE h, long *limits);
DLLIMPORT long _stdcall GetOmsHomeSensors(HANDLE h, long *axes);

/* ---- encoders ----------------------------------------------------------------------- */
DLLIMPORT long _stdcall EnableOmsSlipDetection(HANDLE h, long axis);
DLLIMPORT long _stdcall GetOmsAxisSlipFlag(HANDLE h, long axis, BOOL *slipped);
DLLIMPORT long _stdcall GetSlipFlags(HANDLE h, long *axes);
DLLIMPORT long _stdcall GetAllOmsSlipFlags(HANDLE h, long *axes);
DLLIMPORT long _stdcall ClrSlipFlags(HANDLE h, long axes);
DLLIMPORT long _stdcall ClrOmsSlipFlags(HANDLE h, long axes);
DLLIMPORT long _stdcall GetOmsEncoderFlags(HANDLE h, long axis, long *flags);
DLLIMPORT long _stdcall SetOmsAxisPidEnable(HANDLE h, long axis, long mode);
DLLIMPORT long _stdcall SetOmsEncoderHoldMode(HANDLE h, long axis, long mode);
DLLIMPORT long _stdcall SetOmsEncoderRatio(HANDLE h, long axis, long counts, long steps);
DLLIMPORT long _stdcall SetOmsHoldDeadBand(HANDLE h, long axis, long counts);
DLLIMPORT long _stdcall SetOmsEncoderSlipTolerance(HANDLE h, long axis, long counts);
DLLIMPORT long _stdcall SetOmsHoldGain(HANDLE h, long axis, long gain);
DLLIMPORT long _stdcall SetOmsHoldVelocity(HANDLE h, long axis, long velocity);

/* ---- overtravel ---------------------------------------------------------------------- */
DLLIMPORT long _stdcall SetOmsAxisOvertravelDetect(HANDLE h, long axis, long mode);
DLLIMPORT long _stdcall ConfigureOmsAxisLimitInput(HANDLE h, long axis, long level);
DLLIMPORT long _stdcall SetOmsSoftLimitsMode(HANDLE h, long axis, long mode);

/* ---- general purpose I/O ------------------------------------------------------------ */
DLLIMPORT long _stdcall GetOmsIOBitConfig(HANDLE h, long *outputs);
DLLIMPORT long _stdcall ConfigureAllOmsIOBits(HANDLE h, long outputs);
DLLIMPORT long _stdcall GetAllOmsIOBits(HANDLE h, long *bits);
DLLIMPORT long _stdcall SetAllOmsIOBits(HANDLE h, long bits);
DLLIMPORT long _stdcall GetOmsIOBit(HANDLE h, long bit, long *state);
DLLIMPORT long _stdcall SetOmsIOBit(HANDLE h, long bit, long state);

/* ---- auxiliary outputs --------------------------------------------------------------- */
DLLIMPORT long _stdcall EnableOmsAxisAuxOutAutoMode(HANDLE h, long axis, long mode);
DLLIMPORT long _stdcall SetOmsAxisAuxOutSettleTime(HANDLE h, long axis, long ms);
DLLIMPORT long _stdcall SetOmsAxisAuxOutBit(HANDLE h, long axis, long state);
DLLIMPORT long _stdcall SetSelectedOmsAuxOutBits(HANDLE h, long axes, long state);

/* ---- waiting ------------------------------------------------------------------------- */
DLLIMPORT long _stdcall OmsWait(long ms);

/* ---- the big command buffer ---------------------------------------------------------- */
DLLIMPORT long _stdcall OMS_SetCommandBuffer(HANDLE h, eOMSBuffMode mode, long size);
DLLIMPORT long _stdcall OMS_GetCommandBufferSelection(HANDLE h, eOMSBuffMode *mode);
DLLIMPORT long _stdcall OMS_BigBufferSendBlock(HANDLE h, LPSTR block, long size, long *sent);
DLLIMPORT long _stdcall OMS_GetBigBufferFreeSpace(HANDLE h, long *free_space);
DLLIMPORT long _stdcall OMS_FlushBigBuffer(HANDLE h);

/* ---- maxk's own, not in the vendor's library ------------------------------------------- */
/* Reply lines longer than the library's 4 KiB inbox that were dropped (a MAX board never
 * sends one; the library drops such a line instead of stalling: docs/oms-library.md). */
DLLIMPORT unsigned long _stdcall MaxkOmsDroppedLines(HANDLE h);

#if defined(__cplusplus) && !defined(OMSMAXKMC_BUILD)
/* C++ code passes string literals where the API says LPSTR (MSVC lets it); these
 * overloads take them without a warning and call the functions above. */
inline HANDLE GetOmsHandle(const char *name) { return GetOmsHandle(const_cast<LPSTR>(name)); }
inline long SendOmsQueryCommand(HANDLE h, const char *command, LPSTR reply)
{ return SendOmsQueryCommand(h, const_cast<LPSTR>(command), reply); }
inline long SendAndGetString(HANDLE h, const char *command, LPSTR reply)
{ return SendAndGetString(h, const_cast<LPSTR>(command), reply); }
inline long SendOmsTextCommand(HANDLE h, const char *command)
{ return SendOmsTextCommand(h, const_cast<LPSTR>(command)); }
inline long SendString(HANDLE h, const char *command)
{ return SendString(h, const_cast<LPSTR>(command)); }
inline long OMS_BigBufferSendBlock(HANDLE h, const char *block, long size, long *sent)
{ return OMS_BigBufferSendBlock(h, const_cast<LPSTR>(block), size, sent); }
#endif

#endif /* MAXK_OMSMAXKMC_H */
