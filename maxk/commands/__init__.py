"""The controllers' languages: bytes in, actions on a personality and replies out. One
package a language: `max` (the OMS MAX family's ASCII commands)."""
