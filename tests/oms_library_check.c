/* Every function of the OmsMAXkMC API against a served MAXk-A000 (named by OMS_CHECK_BOARD,
 * a second board by OMS_CHECK_SECOND), as legacy host code calls them, `void main` and all. Compiled and run by
 * tests/test_oms_library.py, which prepares the world around board 1 first:
 *   T limit switches at +3000 and -3000, U home switch 500..560, input bit 3 high.
 * Each check that can be made here is made here (exit 1 with the reason); the values
 * the test compares with the board's own state are printed as `key value` lines. */
#include <windows.h>
#include <OmsMAXkMC.H>

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures;

#define EXPECT(cond, ...)                                                                 \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            fprintf(stderr, "line %d: ", __LINE__);                                      \
            fprintf(stderr, __VA_ARGS__);                                                 \
            fputc('\n', stderr);                                                          \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)
#define OK(call) EXPECT((rc = (call)) == SUCCESS, "%s returned %ld", #call, rc)
#define CODE(call, want) EXPECT((rc = (call)) == (want), "%s returned %ld, not %d", #call, rc, want)

static long rc;

static long motor(HANDLE h, long axis)
{
    long p = -999999;
    OK(GetOmsAxisMotorPosition(h, axis, &p));
    return p;
}

/* Poll the done flag as a host without the ...Wait functions does. */
static void wait_done(HANDLE h, long axes)
{
    long done = 0;
    int i;
    for (i = 0; i < 20000; i++) {
        OK(GetDoneFlags(h, &done));
        if ((done & axes) == axes)
            return;
        OmsWait(1);
    }
    EXPECT(0, "axes %#lx never done", axes);
}

static void wait_stopped(HANDLE h, long axis)
{
    long v = 1;
    int i;
    for (i = 0; i < 20000 && v; i++) {
        OK(GetOmsAxisVelocity(h, axis, &v));
        if (v)
            OmsWait(1);
    }
    EXPECT(v == 0, "axis %#lx still moving at %ld", axis, v);
}

struct worker {
    HANDLE h;
    long expect_x;
    int bad;
};

static void *hammer(void *arg)
{
    struct worker *w = (struct worker *)arg;
    char reply[80];
    int i;
    for (i = 0; i < 150; i++) {
        long p = 0;
        if (SendAndGetString(w->h, "AXRP", reply) != SUCCESS || atol(reply) != w->expect_x)
            w->bad++;
        if (GetOmsAxisMotorPosition(w->h, OMS_X_AXIS, &p) != SUCCESS || p != w->expect_x)
            w->bad++;
    }
    return NULL;
}

static int run(const char *name, const char *second)
{
    char buf[80];
    HANDLE h, h2, other;
    AXES_DATA axes, got;
    POSITION_DATA pos;
    BOOL flag;
    long value, mask;
    eOMSBuffMode mode;
    int i;

    /* ---- handles -------------------------------------------------------------------- */
    EXPECT(GetOmsHandle("OmsMAXk9") == NULL, "a board nobody serves gave a handle");
    EXPECT(GetOmsHandle("OmsMAXp1") == NULL, "another family's name gave a handle");
    EXPECT(GetOmsHandle("OmsMAXk0") == NULL, "board 0 gave a handle");
    h = GetOmsHandle((LPSTR)name);
    if (!h) {
        fprintf(stderr, "no handle for %s\n", name);
        return 1;
    }
    h2 = GetOmsHandle((LPSTR)name); /* a second handle on the same board */
    EXPECT(h2 != NULL, "second handle");
    other = GetOmsHandle((LPSTR)second);
    EXPECT(other != NULL && other != h, "board 2");
    EXPECT(h2 == h, "handles of one board are one handle");

    /* ---- general -------------------------------------------------------------------- */
    GetOmsDllVersion(buf, sizeof buf);
    EXPECT(strstr(buf, "OmsMAXkMC") != NULL, "dll version %s", buf);
    GetOmsDriverVersion(h, buf);
    EXPECT(buf[0] != 0, "driver version");
    OK(GetOmsControllerDescription(h, buf));
    printf("description %s\n", buf);
    OK(SendAndGetString(h, "wy", buf));
    EXPECT(strncmp(buf, "MAXk-A000", 9) == 0, "wy: %s", buf);
    OK(SendOmsQueryCommand(h, "AXRP", buf));
    EXPECT(strcmp(buf, "0") == 0, "AXRP: '%s'", buf);
    OK(SendString(h, ";AZ;PSE;"));
    OK(SendOmsTextCommand(h, "AX;VL50000;AC500000;AY;VL50000;AC500000;"));
    value = GetCmdBufferFree(h);
    EXPECT(value > 0 && value < 1024, "free %ld", value);

    /* ---- velocity and acceleration ------------------------------------------------ */
    OK(SetOmsAxisBaseVelocity(h, OMS_X_AXIS, 100));
    OK(SetOmsAxisVelocity(h, OMS_X_AXIS, 40000));
    OK(SetOmsAxisAcceleration(h, OMS_X_AXIS, 400000));
    OK(GetOmsAxisAcceleration(h, OMS_X_AXIS, &value));
    EXPECT(value == 400000, "RC %ld", value);
    OK(GetSelectedOmsAccelerations(h, OMS_X_AXIS | OMS_Y_AXIS, &got));
    EXPECT(got.X == 400000 && got.Y == 500000, "accelerations %ld %ld", got.X, got.Y);
    CODE(SetOmsAxisVelocity(h, OMS_X_AXIS, 4000001), INVALID_PARAMETER);
    CODE(SetOmsAxisVelocity(h, OMS_X_AXIS | OMS_Y_AXIS, 1000), INVALID_AXIS_SELECTION);
    CODE(SetOmsAxisAcceleration(h, OMS_X_AXIS, 0), INVALID_PARAMETER);
    CODE(MoveOmsAxisRel(h, 0, 10), INVALID_AXIS_SELECTION);
    CODE(MoveOmsAxisRel(h, 0x400, 10), INVALID_AXIS_SELECTION);
    CODE(MoveOmsIndependentRel(h, 0x800, &axes), INVALID_AXIS_SELECTION);

    /* ---- one-axis moves ---------------------------------------------------------------- */
    OK(MoveOmsAxisRelWait(h, OMS_X_AXIS, 10000, 20000));
    EXPECT(motor(h, OMS_X_AXIS) == 10000, "X after MR10000");
    OK(GetOmsAxisDoneFlag(h, OMS_X_AXIS, &flag));
    EXPECT(flag == TRUE, "X done");
    OK(GetAllOmsDoneFlags(h, &mask));
    EXPECT(mask & OMS_X_AXIS, "done mask %#lx", mask);
    OK(ClrDoneFlags(h, OMS_X_AXIS));
    OK(GetOmsAxisDoneFlag(h, OMS_X_AXIS, &flag));
    EXPECT(flag == FALSE, "X done cleared");
    OK(MoveOmsAxisAbsWait(h, OMS_X_AXIS, -2500, 20000));
    EXPECT(motor(h, OMS_X_AXIS) == -2500, "X after MA-2500");
    OK(ClrOmsDoneFlags(h, OMS_X_AXIS));
    OK(MoveOmsAxisAbs(h, OMS_Y_AXIS, 700));
    wait_done(h, OMS_Y_AXIS);
    OK(MoveOmsAxisRel(h, OMS_Y_AXIS, 300));
    wait_done(h, OMS_Y_AXIS);
    EXPECT(motor(h, OMS_Y_AXIS) == 1000, "Y after MA700 MR300");

    /* ---- several axes ------------------------------------------------------------------ */
    memset(&axes, 0, sizeof axes);
    axes.X = 100, axes.Y = 200, axes.Z = 999; /* Z is not in the mask: it stays */
    OK(MoveOmsIndependentAbsWait(h, OMS_X_AXIS | OMS_Y_AXIS, &axes, 20000));
    axes.X = 10, axes.Z = -50;
    OK(MoveOmsIndependentRelWait(h, OMS_X_AXIS | OMS_Z_AXIS, &axes, 20000));
    OK(MoveOmsIndependentRel(h, OMS_X_AXIS | OMS_Z_AXIS, &axes));
    wait_done(h, OMS_X_AXIS | OMS_Z_AXIS);
    OK(MoveOmsIndependentAbs(h, OMS_Y_AXIS, &axes)); /* Y to 200 again */
    wait_done(h, OMS_Y_AXIS);
    axes.X = 1000, axes.Y = 2000;
    OK(MoveOmsLinearAbsWait(h, OMS_X_AXIS | OMS_Y_AXIS, &axes, 20000));
    axes.X = -500, axes.Y = -500;
    OK(MoveOmsLinearRelWait(h, OMS_X_AXIS | OMS_Y_AXIS, &axes, 20000));
    OK(MoveOmsLinearRel(h, OMS_X_AXIS | OMS_Y_AXIS, &axes));
    wait_done(h, OMS_X_AXIS | OMS_Y_AXIS);
    axes.X = 300, axes.Y = 400;
    OK(MoveOmsLinearAbs(h, OMS_X_AXIS | OMS_Y_AXIS, &axes));
    wait_done(h, OMS_X_AXIS | OMS_Y_AXIS);
    OK(GetSelectedOmsMotorPositions(h, OMS_X_AXIS | OMS_Y_AXIS | OMS_Z_AXIS, &got));
    EXPECT(got.X == 300 && got.Y == 400 && got.Z == -100, "after AA moves %ld %ld %ld", got.X, got.Y, got.Z);
    axes.X = 50, axes.Y = 60;
    OK(MoveOmsIndependentRelMtWait(h, OMS_X_AXIS | OMS_Y_AXIS, &axes, 20000));
    OK(MoveOmsIndependentRelMt(h, OMS_X_AXIS, &axes));
    wait_done(h, OMS_X_AXIS);
    axes.X = 1200, axes.Y = 1300;
    OK(MoveOmsIndependentAbsMtWait(h, OMS_X_AXIS | OMS_Y_AXIS, &axes, 20000));
    axes.Y = 1500;
    OK(MoveOmsIndependentAbsMt(h, OMS_Y_AXIS, &axes));
    wait_done(h, OMS_Y_AXIS);
    axes.X = 2000, axes.Y = 2200;
    OK(MoveOmsLinearAbsMtWait(h, OMS_X_AXIS | OMS_Y_AXIS, &axes, 20000));
    OK(MoveOmsLinearAbsMt(h, OMS_X_AXIS | OMS_Y_AXIS, &axes)); /* already there */
    wait_done(h, OMS_X_AXIS | OMS_Y_AXIS);
    axes.X = -100, axes.Y = 100;
    OK(MoveOmsLinearRelMtWait(h, OMS_X_AXIS | OMS_Y_AXIS, &axes, 20000));
    OK(MoveOmsLinearRelMt(h, OMS_X_AXIS | OMS_Y_AXIS, &axes));
    wait_done(h, OMS_X_AXIS | OMS_Y_AXIS);
    OK(GetMotorPositions(h, &got));
    EXPECT(got.X == 1800 && got.Y == 2400 && got.Z == -100, "after AM moves %ld %ld %ld", got.X, got.Y, got.Z);
    OK(GetEncoderPositions(h, &got));
    EXPECT(got.Z == -100, "Z encoder %ld", got.Z);
    OK(GetSelectedOmsEncoderPositions(h, OMS_Z_AXIS, &got));
    OK(GetOmsAxisEncoderPosition(h, OMS_Z_AXIS, &value));
    EXPECT(value == -100 && got.Z == -100, "Z encoder %ld %ld", value, got.Z);
    OK(GetAbsoluteEncoderPositions(h, &got));
    OK(GetOmsAxisAbsoluteEncoderPosition(h, OMS_Z_AXIS, &value));
    EXPECT(value == got.Z, "absolute encoder %ld %ld", value, got.Z);
    OK(GetPositionData(h, &pos));
    EXPECT(pos.X.Motor == 1800 && pos.Y.Motor == 2400 && pos.Z.Encoder == -100,
           "position data %ld %ld %ld", pos.X.Motor, pos.Y.Motor, pos.Z.Encoder);

    /* ---- jog, stop, fractional, one step, position load --------------------------------- */
    OK(MoveOmsAxisIndefinite(h, OMS_R_AXIS, 20000));
    for (i = 0, value = 0; i < 5000 && value != 20000; i++) {
        OK(GetOmsAxisVelocity(h, OMS_R_AXIS, &value));
        OmsWait(1);
    }
    EXPECT(value == 20000, "R jog velocity %ld", value);
    OK(GetSelectedOmsVelocities(h, OMS_R_AXIS, &got));
    EXPECT(got.R == 20000, "selected velocity %ld", got.R);
    OK(StopOmsAxis(h, OMS_R_AXIS));
    wait_stopped(h, OMS_R_AXIS);
    OK(MoveOmsAxisFractional(h, OMS_S_AXIS, 1000.5));
    OmsWait(20);
    OK(GetOmsAxisVelocity(h, OMS_S_AXIS, &value));
    EXPECT(value >= 1000 && value <= 1001, "S fractional jog %ld", value);
    OK(StopAllOmsAxes(h));
    wait_stopped(h, OMS_S_AXIS);
    OK(MoveOmsAxisOneStep(h, OMS_W_AXIS, POSITIVE));
    OK(MoveOmsAxisOneStep(h, OMS_W_AXIS, POSITIVE));
    OK(MoveOmsAxisOneStep(h, OMS_W_AXIS, NEGATIVE));
    CODE(MoveOmsAxisOneStep(h, OMS_W_AXIS, 7), INVALID_PARAMETER);
    OK(SetOmsAxisPosition(h, OMS_K_AXIS, 12345));
    /* W passes 1 on its way (+1, +1, -1): wait until it stays there for 200 reads */
    for (i = 0, value = 0; i < 5000 && value < 200; i++) {
        value = motor(h, OMS_W_AXIS) == 1 && motor(h, OMS_K_AXIS) == 12345 ? value + 1 : 0;
        OmsWait(1);
    }
    EXPECT(motor(h, OMS_W_AXIS) == 1 && motor(h, OMS_K_AXIS) == 12345, "W one steps, K loaded");

    /* ---- homing against the world's switch (U home 500..560) ---------------------------- */
    OK(SendString(h, "AU;VL20000;AC200000;"));
    OK(DefineOmsHomeAsSwitchOpen(h, OMS_U_AXIS));
    OK(DefineOmsHomeAsSwitchClosed(h, OMS_U_AXIS));
    OK(HomeOmsAxisFwdUseSwitchWait(h, OMS_U_AXIS, 0, 20000));
    printf("home_fwd_U %ld\n", motor(h, OMS_U_AXIS));
    OK(MoveOmsAxisAbsWait(h, OMS_U_AXIS, 30, 20000)); /* onto the switch (counter 0 at its edge) */
    OK(GetOmsHomeSensors(h, &mask));
    printf("home_sensors %ld\n", mask);
    OK(GetOmsAxisFlags(h, OMS_U_AXIS, &value));
    printf("flags_U %ld\n", value);
    OK(MoveOmsAxisRelWait(h, OMS_U_AXIS, 3000, 20000));
    OK(HomeOmsAxisRevUseSwitch(h, OMS_U_AXIS, 100));
    wait_done(h, OMS_U_AXIS);
    printf("home_rev_U %ld\n", motor(h, OMS_U_AXIS));
    OK(MoveOmsAxisRelWait(h, OMS_U_AXIS, -3000, 20000));
    OK(HomeOmsAxisFwdUseSwitch(h, OMS_U_AXIS, 7));
    wait_done(h, OMS_U_AXIS);
    printf("home_fwd2_U %ld\n", motor(h, OMS_U_AXIS));
    OK(MoveOmsAxisRelWait(h, OMS_U_AXIS, 3000, 20000));
    OK(HomeOmsAxisRevUseSwitchWait(h, OMS_U_AXIS, -5, 20000));
    printf("home_rev2_U %ld\n", motor(h, OMS_U_AXIS));
    /* encoder homing: HE, on an axis with an encoder (Z) and its index mark */
    OK(SendString(h, "AZ;VL20000;AC200000;"));
    OK(HomeOmsAxisFwdUseEncoderWait(h, OMS_Z_AXIS, 0, 20000));
    printf("home_enc_fwd_Z %ld\n", motor(h, OMS_Z_AXIS));
    OK(MoveOmsAxisRelWait(h, OMS_Z_AXIS, 2000, 20000));
    OK(HomeOmsAxisRevUseEncoderWait(h, OMS_Z_AXIS, 0, 20000));
    printf("home_enc_rev_Z %ld\n", motor(h, OMS_Z_AXIS));
    OK(HomeOmsAxisFwdUseEncoder(h, OMS_Z_AXIS, 0));
    wait_done(h, OMS_Z_AXIS);
    OK(HomeOmsAxisRevUseEncoder(h, OMS_Z_AXIS, 0));
    wait_done(h, OMS_Z_AXIS);

    /* ---- limits: the world's T switches at +3000 / -3000 -------------------------------- */
    OK(SetOmsAxisOvertravelDetect(h, OMS_T_AXIS, MODE_ON));
    OK(ConfigureOmsAxisLimitInput(h, OMS_T_AXIS, LOW));
    OK(SetOmsSoftLimitsMode(h, OMS_T_AXIS, MODE_OFF));
    OK(GetOmsAxisLimitFlag(h, OMS_T_AXIS, &flag));
    EXPECT(flag == FALSE, "T limit before");
    OK(FindOmsAxisFwdLimit(h, OMS_T_AXIS, 20000, 20000));
    OK(GetLimitFlags(h, &mask));
    EXPECT(mask == OMS_T_AXIS_POS_LIMIT, "limit flags %#lx", mask);
    OK(GetOmsAxisLimitFlag(h, OMS_T_AXIS, &flag));
    EXPECT(flag == TRUE, "T limit flag");
    wait_stopped(h, OMS_T_AXIS);
    OK(GetOmsLimitSensors(h, &mask));
    EXPECT(mask == OMS_T_AXIS_POS_LIMIT, "limit sensors %#lx", mask);
    OK(GetOmsAxisFlags(h, OMS_T_AXIS, &value));
    EXPECT(value & AXIS_OVERTRAVEL, "T flags %#lx", value);
    printf("limit_T %ld\n", motor(h, OMS_T_AXIS));
    OK(ClrLimitFlags(h, OMS_T_AXIS_POS_LIMIT));
    OK(GetAllOmsLimitFlags(h, &mask));
    EXPECT(mask == 0, "limit flags cleared %#lx", mask);
    OK(FindOmsAxisRevLimit(h, OMS_T_AXIS, 20000, 20000));
    wait_stopped(h, OMS_T_AXIS);
    OK(GetLimitFlags(h, &mask));
    EXPECT(mask == OMS_T_AXIS_NEG_LIMIT, "limit flags %#lx", mask);
    OK(GetOmsLimitSensors(h, &mask));
    EXPECT(mask == OMS_T_AXIS_NEG_LIMIT, "limit sensors %#lx", mask);
    OK(ClrOmsLimitFlags(h, OMS_T_AXIS_NEG_LIMIT));
    OK(GetLimitFlags(h, &mask));
    EXPECT(mask == 0, "limit flags cleared %#lx", mask);
    CODE(FindOmsAxisFwdLimit(h, OMS_T_AXIS, 0, 100), INVALID_PARAMETER);

    /* ---- the controller's command-error flag --------------------------------------------- */
    OK(SendString(h, "QQ;"));
    OK(SendAndGetString(h, "AXRP", buf)); /* the board has taken QQ by now */
    for (i = 0, value = 0; i < 2000 && !value; i++) {
        OK(GetStatusFlags(h, &value));
        if (!value)
            OmsWait(1);
    }
    EXPECT(value == COMMAND_ERROR, "status %#lx", value);
    OK(ClrStatusFlags(h, COMMAND_ERROR));
    OK(GetOmsControllerFlags(h, &value));
    EXPECT(value == 0, "status cleared %#lx", value);
    OK(ClrOmsControllerFlags(h, COMMAND_ERROR));

    /* ---- general purpose I/O (input 3 is high in the world) ------------------------------ */
    OK(GetOmsIOBitConfig(h, &value));
    EXPECT(value == 0xFF00, "bit directions %#lx", value);
    OK(ConfigureAllOmsIOBits(h, 0xFF00));
    OK(GetOmsIOBit(h, 3, &value));
    EXPECT(value == 1, "input 3 %ld", value);
    OK(SetOmsIOBit(h, 9, HIGH));
    OK(GetOmsIOBit(h, 9, &value));
    EXPECT(value == 1, "output 9 %ld", value);
    CODE(SetOmsIOBit(h, 16, HIGH), INVALID_BIT_NUMBER);
    CODE(GetOmsIOBit(h, -1, &value), INVALID_BIT_NUMBER);
    OK(SetAllOmsIOBits(h, 0x8200));
    OK(GetAllOmsIOBits(h, &value));
    EXPECT(value == 0x8208, "all bits %#lx", value);
    OK(SetOmsIOBit(h, 12, HIGH));
    OK(SetOmsIOBit(h, 15, LOW));
    OK(GetAllOmsIOBits(h, &value));
    printf("io_check %ld\n", value); /* the test looks at the world's lines, then answers */
    fflush(stdout);
    EXPECT(getchar() == '\n', "the test's go-ahead");

    /* ---- aux outputs ------------------------------------------------------------------- */
    OK(EnableOmsAxisAuxOutAutoMode(h, OMS_X_AXIS, MODE_OFF));
    OK(SetOmsAxisAuxOutSettleTime(h, OMS_X_AXIS, 10));
    OK(SetOmsAxisAuxOutBit(h, OMS_X_AXIS, HIGH));
    OK(SendAndGetString(h, "AXAB?", buf));
    EXPECT(strstr(buf, "=h") != NULL, "X aux %s", buf);
    OK(SetSelectedOmsAuxOutBits(h, OMS_Y_AXIS | OMS_Z_AXIS, HIGH));
    OK(SendAndGetString(h, "AZAB?", buf));
    EXPECT(strstr(buf, "=h") != NULL, "Z aux %s", buf);
    OK(SendAndGetString(h, "ATAB?", buf));
    EXPECT(strstr(buf, "=l") != NULL, "T aux %s", buf);
    OK(EnableOmsAxisAuxOutAutoMode(h, OMS_X_AXIS, MODE_ON));

    /* ---- encoders (Z has one) ------------------------------------------------------------ */
    OK(EnableOmsSlipDetection(h, OMS_Z_AXIS));
    OK(SetOmsEncoderSlipTolerance(h, OMS_Z_AXIS, 10));
    OK(SetOmsEncoderRatio(h, OMS_Z_AXIS, 1, 1));
    OK(SetOmsHoldDeadBand(h, OMS_Z_AXIS, 2));
    OK(SetOmsHoldGain(h, OMS_Z_AXIS, 100));
    OK(SetOmsHoldVelocity(h, OMS_Z_AXIS, 1000));
    OK(SetOmsEncoderHoldMode(h, OMS_Z_AXIS, MODE_OFF));
    OK(SetOmsAxisPidEnable(h, OMS_Z_AXIS, MODE_OFF));
    CODE(SetOmsEncoderRatio(h, OMS_Z_AXIS, 0, 1), INVALID_PARAMETER);
    OK(GetOmsEncoderFlags(h, OMS_Z_AXIS, &value));
    EXPECT(value & SLIP_DETECT_ENABLED, "Z encoder flags %#lx", value);
    OK(GetOmsAxisSlipFlag(h, OMS_Z_AXIS, &flag));
    EXPECT(flag == FALSE, "Z slip");
    OK(GetSlipFlags(h, &mask));
    OK(GetAllOmsSlipFlags(h, &value));
    EXPECT(mask == 0 && value == 0, "slip flags %#lx", mask);
    OK(ClrSlipFlags(h, OMS_Z_AXIS));
    OK(ClrOmsSlipFlags(h, OMS_Z_AXIS));
    /* S gets an encoder and slip detection; the test makes its stage miss 50 steps */
    OK(SendString(h, "AS;PSE;IS;ES10;"));
    OK(SendAndGetString(h, "ASRP", buf)); /* taken by the board by now */
    printf("world slip\n");
    fflush(stdout);
    EXPECT(getchar() == '\n', "the test's go-ahead");
    OK(MoveOmsAxisRelWait(h, OMS_S_AXIS, 1000, 20000));
    OK(GetOmsAxisSlipFlag(h, OMS_S_AXIS, &flag));
    EXPECT(flag == TRUE, "S slipped");
    OK(GetSlipFlags(h, &mask));
    EXPECT(mask == OMS_S_AXIS, "slip flags %#lx", mask);
    OK(GetOmsEncoderFlags(h, OMS_S_AXIS, &value));
    EXPECT(value & AXIS_SLIPPED, "S encoder flags %#lx", value);
    OK(ClrOmsSlipFlags(h, OMS_S_AXIS));
    OK(GetAllOmsSlipFlags(h, &mask));
    EXPECT(mask == 0, "slip flags cleared %#lx", mask);

    /* ---- ramps -------------------------------------------------------------------------- */
    OK(SelectOmsCosineRamp(h, OMS_X_AXIS));
    OK(SelectOmsParabolicRamp(h, OMS_X_AXIS, 3));
    OK(SelectOmsSCurveRamp(h, OMS_X_AXIS, 50));
    OK(SelectOmsLinearRamp(h, OMS_X_AXIS));
    CODE(SelectOmsParabolicRamp(h, OMS_X_AXIS, 9), INVALID_PARAMETER);

    /* ---- the big command buffer ---------------------------------------------------------- */
    OK(OMS_SetCommandBuffer(h, OMS_BIG_CMD_BUFFER_MODE, 4000));
    OK(OMS_GetCommandBufferSelection(h, &mode));
    EXPECT(mode == OMS_BIG_CMD_BUFFER_MODE, "buffer mode %d", (int)mode);
    OK(ClrDoneFlags(h, OMS_X_AXIS));
    OK(OMS_BigBufferSendBlock(h, "AX;MR100;GO;ID;", 15, &value));
    EXPECT(value == 15, "sent %ld", value);
    wait_done(h, OMS_X_AXIS);
    EXPECT(motor(h, OMS_X_AXIS) == 1900, "X after the block");
    OK(OMS_GetBigBufferFreeSpace(h, &value));
    EXPECT(value > 0, "big buffer free %ld", value);
    OK(OMS_FlushBigBuffer(h));
    OK(OMS_SetCommandBuffer(h, OMS_NORMAL_CMD_BUFFER_MODE, 0));
    OK(OMS_GetCommandBufferSelection(h, &mode));
    EXPECT(mode == OMS_NORMAL_CMD_BUFFER_MODE, "buffer mode %d", (int)mode);

    /* ---- a move longer than its limit ----------------------------------------------------- */
    OK(SetOmsAxisVelocity(h, OMS_V_AXIS, 1000));
    CODE(MoveOmsAxisRelWait(h, OMS_V_AXIS, 1000000, 150), MOVE_TIME_OUT);
    OK(GetOmsAxisDoneFlag(h, OMS_V_AXIS, &flag));
    EXPECT(flag == FALSE, "V done while still moving");
    OK(KillAllOmsMotion(h));
    OK(SendAndGetString(h, "AVRV", buf));
    EXPECT(strcmp(buf, "0") == 0, "V after the kill: %s", buf);

    /* ---- threads on two handles of the board, and the second board ---------------------- */
    {
        struct worker w[4];
        pthread_t t[4];
        long x = motor(h, OMS_X_AXIS);
        for (i = 0; i < 4; i++) {
            w[i].h = i % 2 ? h2 : h;
            w[i].expect_x = x;
            w[i].bad = 0;
            pthread_create(&t[i], NULL, hammer, &w[i]);
        }
        OK(MoveOmsAxisRelWait(other, OMS_X_AXIS, 4321, 20000));
        for (i = 0; i < 4; i++) {
            pthread_join(t[i], NULL);
            EXPECT(w[i].bad == 0, "thread %d saw %d bad replies", i, w[i].bad);
        }
        EXPECT(motor(other, OMS_X_AXIS) == 4321, "board 2 X");
        EXPECT(motor(h, OMS_X_AXIS) == x, "board 1 X untouched");
    }

    /* ---- print the final state for the test to compare with the board ------------------- */
    OK(GetMotorPositions(h, &got));
    printf("motor %ld %ld %ld %ld %ld %ld %ld %ld %ld %ld\n", got.X, got.Y, got.Z, got.T, got.U,
           got.V, got.R, got.S, got.W, got.K);

    /* ---- reset, close ------------------------------------------------------------------- */
    OK(ResetOmsController(h));
    OK(SendAndGetString(h, "AXRP", buf));
    EXPECT(strcmp(buf, "0") == 0, "X after reset: %s", buf);
    CloseOmsHandle(h2);
    OK(SendAndGetString(h, "WY", buf)); /* h still open: a board closes with its last handle */
    CloseOmsHandle(h);
    CloseOmsHandle(other);
    CODE(SendString(h, "WY"), COMMAND_TIME_OUT); /* closed: nothing takes it */
    CODE(SendString(NULL, "WY"), COMMAND_TIME_OUT);
    printf("failures %d\n", failures);
    return failures ? 1 : 0;
}

/* The board names come from the environment: void main(void) has no arguments. */
void main(void)
{
    const char *first = getenv("OMS_CHECK_BOARD");
    const char *second = getenv("OMS_CHECK_SECOND");
    exit(run(first ? first : "OmsMAXk1", second ? second : "OmsMAXk2"));
}
