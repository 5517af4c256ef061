#pragma once
/// \file expected_uncertainty.h
/// (being written)
