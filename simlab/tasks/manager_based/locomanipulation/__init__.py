"""Loco-manipulation tasks (Isaac Lab's ``manager_based/locomanipulation``)."""
